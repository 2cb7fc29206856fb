#pragma once
namespace gdof {
inline const char* version() { return GDOF_VERSION_STRING; }
}
