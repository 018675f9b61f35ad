// The OpenImageIO module: a shared library (brdfbake_oiio.so, built from io/oiio_module.cpp) that
// reads the image formats the focused readers of io/image_file do not (PNG, TIFF, JPEG, PSD, DDS,
// ...). The program does not link OpenImageIO: linking it costs every run ~150 ms and ~130 MiB
// for the ~250 libraries Debian's build pulls in and their initialisers, even `--help`. The module
// is loaded with dlopen the first time such a file is read.
//
// Found, in order: the file $BRDFBAKE_OIIO_MODULE names (only it, when set); else, when this code
// is in a shared object (the Python package's extension), brdfbake_oiio.so in that object's own
// folder only; else brdfbake_oiio.so beside the running executable, ../lib/brdfbake/brdfbake_oiio.so
// from it, and the build tree's copy for an executable inside the build tree (tests, benchmarks).
// Never a build-time path for anything else: pip builds in a temporary folder that is deleted and
// whose path any local user could create again with a module of their own.
//
// The interface is plain C, versioned, so that the module and the program need not share C++
// types across the boundary.
#pragma once

#include <cstddef>

extern "C" {

// Bumped whenever a struct or a signature below changes; the loader refuses another version.
#define BRDFBAKE_OIIO_ABI_VERSION 3

struct brdfbake_oiio_image {
  int width;
  int height;
  int channels;
  float* pixels;        // width x height x channels, row 0 first (allocated by the module)
  char* channel_names;  // comma-separated, in OpenImageIO's order (allocated by the module)
  char* description;    // e.g. "tiff 640x480, 3 channel(s), uint8" (allocated by the module)
  // What was done to integer-coded values, e.g. "8-bit sRGB (oiio:ColorSpace) decoded to linear",
  // or empty (float data, or data stated linear); allocated by the module.
  char* transfer_note;
};

// Returns non-zero when the read should stop (a stop request: brdfbake/cancel.hpp).
typedef int (*brdfbake_oiio_stop_fn)(void);

// int brdfbake_oiio_abi_version(void): BRDFBAKE_OIIO_ABI_VERSION of the module.
typedef int (*brdfbake_oiio_abi_version_fn)(void);
// Reads level 0 of subimage 0 of `path` as linear float into `out`; images of more than max_pixels
// pixels, or whose decoding takes more than max_bytes (0: no limit; io/image_limits.hpp, counting
// the module's buffer and the caller's copy), are refused before decoding. Integer-coded colour
// channels are decoded to linear from the file's colour space (oiio:ColorSpace: sRGB, linear,
// GammaN; none stated: sRGB for 8-bit data, the convention for untagged images, as stored for
// 16-bit; any other is refused); alpha
// stays as stored. `should_stop` (may be null) is asked between parts of the read; when it says
// stop, the read ends with 2 and the reason "cancelled". Returns 0 on success; otherwise a
// one-line reason (without the path) in `error` (NUL-terminated, at most error_size bytes) and
// `out` untouched.
typedef int (*brdfbake_oiio_read_fn)(const char* path, unsigned long long max_pixels, unsigned long long max_bytes,
                                     brdfbake_oiio_stop_fn should_stop, brdfbake_oiio_image* out, char* error,
                                     size_t error_size);
// Frees what brdfbake_oiio_read allocated in `image`.
typedef void (*brdfbake_oiio_free_fn)(brdfbake_oiio_image* image);

}  // extern "C"

#include <string>
#include <vector>

namespace brdfbake::io {

// The loaded module's functions. Throws Error with a one-line reason naming where it looked when
// the module cannot be loaded (missing, wrong ABI version, missing symbols).
struct OiioModule {
  brdfbake_oiio_read_fn read = nullptr;
  brdfbake_oiio_free_fn free = nullptr;
  std::string path;  // the file loaded
};
const OiioModule& oiio_module();

// Where oiio_module() looks, in order (above).
std::vector<std::string> oiio_module_candidates();

// Whether the module is loaded in this process (for tests of laziness).
bool oiio_module_loaded();

}  // namespace brdfbake::io
