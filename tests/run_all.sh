#!/usr/bin/env bash
# The test command: installs dependencies, builds everything, runs every test;
# then the reliability runs (docs/reliability.md): the suite again under
# AddressSanitizer + UndefinedBehaviorSanitizer (.ci/sanitize asan, its own
# build folder) and a short pass of every fuzz harness over its kept corpus
# (.ci/fuzz, GDOF_FUZZ_SECONDS each, default 30). GDOF_SKIP_SANITIZE=1 skips
# both (e.g. locally, where they add the most time).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/.ci/install-deps"
bash "$root/.ci/build"
(cd "${GDOF_BUILD_DIR:-$root/build}" && ctest --output-on-failure -j "${GDOF_JOBS:-$(nproc)}" --timeout 900)
if [[ "${GDOF_SKIP_SANITIZE:-0}" != 1 ]]; then
  bash "$root/.ci/sanitize" asan
  bash "$root/.ci/fuzz" --seconds "${GDOF_FUZZ_SECONDS:-30}"
fi
