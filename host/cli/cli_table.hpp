// The commands that bake one table (lut, fresnel, thin-film, prefilter, irradiance, eval, tabulate):
// their options and help are generated from the kind's schema (brdfbake/tables.hpp), so an option
// exists exactly when the job field does, and they bake and write through the same registry calls as
// a job (a parity test holds them to it).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/tables.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

// An option per parameter of `schema` (a flag whose default is true becomes --no-NAME); the help
// says the range or choices and the default.
void add_schema_options(cxxopts::Options& options, const std::vector<ParamDef>& schema);
// The parameters given on the command line, typed; errors name the option as typed.
Params schema_params(const cxxopts::ParseResult& r, const std::vector<ParamDef>& schema);
// Refuses an option of `schema` typed by two of its spellings (--chain-size with its alias
// --cube-size): cxxopts would keep the last one silently. Throws UsageError, one line.
void refuse_two_spellings(int argc, char** argv, const std::vector<ParamDef>& schema);
// Rewrites "--n" as "-n" for the one-letter parameters of `schema` (cxxopts takes long names of two
// characters or more).
std::vector<std::string> one_letter_options(int argc, char** argv, const std::vector<ParamDef>& schema);

struct TableCommand {
  std::string name;         // "lut"
  std::string description;  // one line for --help
  std::string example;      // one example command for --help
  // Extra options and modes of the command (e.g. fresnel --list-materials), handled before table mode:
  // return an exit code to stop there.
  std::function<void(cxxopts::Options&)> add_extra;
  std::function<std::optional<int>(const cxxopts::ParseResult&)> handle_extra;
  std::vector<std::string> extra_names;  // their option names, which table mode refuses
};

// The one-table command called `name` (cmd_tables.cpp), or nullptr.
const TableCommand* table_command(const std::string& name);

// Parses the command line into a validated request, opens the backend, bakes, writes and prints the
// summary line; the whole life of a one-table command.
int run_table_command(const TableCommand& command, int argc, char** argv);

}  // namespace brdfbake::cli
