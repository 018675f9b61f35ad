// The files of a request checked as a set before anything is baked (docs/RELIABILITY.md, "Special
// files" and "Outputs"): what each output names (a device, a FIFO, standard output as a file), no
// output that is the same file as an input (by device and inode, whatever its name), and no two
// outputs of one job on one path (normalised, with the case as the output folder's file system
// treats it), inside another's folder output or under another's file.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/job.hpp"
#include "brdfbake/tables.hpp"

namespace brdfbake {

// A file a request reads or writes, with the field that names it ("environment", "input",
// "output", "sh_json").
struct RequestFile {
  std::string field;
  std::string path;
  bool folder = false;  // an output written as a folder of files (a cube as images)
  std::string beside;   // a file written or read beside the field's own ("its NAME.json"), else ""
};
// The files a validated request reads: its environment's files (builtins and "-" left out), its
// path parameters (material, input) and what its family reads beside them (a bake folder's files).
std::vector<RequestFile> table_input_files(const TableRequest& request);
// The files it writes: its output ("-" left out), its output-only path parameters (sh_json) and what
// its family writes beside the output (the preview's NAME.json, NAME_splitsum.exr, NAME_reference.exr).
std::vector<RequestFile> table_output_files(const TableRequest& request);

// A one-table command: each output against the special-file policy (the main output may be a
// stream when `output_streams`: CSV tables, eval), no output the same file as an input, no two
// outputs on one path. Throws Error (bad input) naming the options as `naming` spells them.
void check_table_files(const TableRequest& request, const FieldNaming& naming, bool output_streams);

// A job's outputs as paths inside its folder, before anything is baked (validate_job calls it with
// `ignore_case` false; run_job again with the case the folder's file system has): two tables, or a
// table's sh_json and another's output, on one path; an output inside another table's folder output
// or under another's file. Throws Error "<origin>: tables[i].<field>: ..." naming both fields.
void check_job_output_set(const Job& job, bool ignore_case);

// Everything check_job_output_set checks, with the case of the file system `folder` is on, and the
// files: no output inside `folder` that is a device, a FIFO or a socket, or the same file as an
// input of the job (its environments, materials, pair files, the job file itself).
// `engine_name` is the NAME of an engine target's files when the run gives one (else the job's, else
// the folder's name); the target's files and the preview's (bake --preview) are outputs too.
void check_job_files(const Job& job, const std::string& folder, const std::string& engine_name = "");

// A command outside the table kinds (view, report): none of `outputs` is a folder, or the same file
// as one of `inputs` (a folder input stands for its regular files two levels down: a bake's folder).
// Throws Error "<output field>: '<path>' is the same file as <input field> ('<path>'): ...".
void check_outputs_not_inputs(const std::vector<RequestFile>& outputs, const std::vector<RequestFile>& inputs);

// Whether the file system holding `folder` (or its nearest existing parent) treats names that differ
// only in case as one file; probed with a temporary file, false when it cannot be probed.
bool folder_ignores_case(const std::string& folder);

}  // namespace brdfbake
