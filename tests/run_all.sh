#!/usr/bin/env bash
# The test command: installs dependencies, builds everything, runs every test.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/.ci/install-deps"
bash "$root/.ci/build"
cd "${GDOF_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "${GDOF_JOBS:-$(nproc)}" --timeout 900
