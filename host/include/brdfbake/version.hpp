#pragma once
namespace brdfbake {
inline constexpr const char* kVersion = "0.1.0";
}
