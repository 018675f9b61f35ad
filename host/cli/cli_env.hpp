// Options shared by the commands that read an environment and write a cubemap (prefilter,
// irradiance).
#pragma once

#include <string>

#include "brdfbake/environment.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

// --sanitize, --pixel, --layout, --image-format, --dds-legacy.
void add_cube_output_options(cxxopts::Options& options);

// The cube container that `path` names (its extension, or a folder), with --dds-legacy applied.
CubeFormat cube_container_option(const cxxopts::ParseResult& r, const std::string& path);
// --pixel, --layout and --image-format.
CubeWriteOptions cube_write_options(const cxxopts::ParseResult& r);

// A path whose writability stands for the output: a file inside a folder output when the folder
// exists, else the folder itself (created later beside its siblings); other outputs as they are.
std::string output_probe(const std::string& path, CubeFormat format);

// Loads --env (with --sanitize), saying on standard error what was replaced unless quiet.
EnvImage load_environment_option(const cxxopts::ParseResult& r, bool quiet);

}  // namespace brdfbake::cli
