// The version, from project() in CMakeLists.txt.
#pragma once

#ifndef BRDFBAKE_VERSION
#define BRDFBAKE_VERSION "unknown"
#endif

namespace brdfbake {
inline constexpr const char* kVersion = BRDFBAKE_VERSION;
}
