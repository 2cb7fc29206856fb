// Placeholder until the CLI lands (replaced in this issue).
#include <cstdio>
#include "gdof/version.h"
int main() { std::printf("gdof %s\n", gdof::version()); return 0; }
