// Reading back the tables that write_table writes (brdfbake/io.hpp): .exr, .png (16-bit, with
// png_scale undone where recorded), .hdr (with its FILE.json sidecar), .ktx2 (2-D), .csv and the C
// header .h, with the channel names and metadata each records. Where a format stores no
// coordinates (.exr .png .ktx2 .h), x and y come from the x_axis / y_axis (or axes) metadata when it
// states a rule this reader knows (cell centres or end points over [0, 1] or a stated range, in
// units of pi/2 where it says so); otherwise they are the column and row indices, named "column"
// and "row".
#pragma once

#include <string>
#include <vector>

#include "brdfbake/table.hpp"

namespace brdfbake::io {

// The format is chosen by the extension. Throws Error("cannot read '<path>': <reason>").
Table read_table(const std::string& path);

// The coordinates of `n` cells along an axis described by `rule` (e.g. "n_dot_v = (i + 0.5) /
// width, the cell centre of column i"): fills *name and *values and returns true when the rule is
// one this reader knows.
bool axis_from_rule(const std::string& rule, int n, std::string* name, std::vector<double>* values);

}  // namespace brdfbake::io
