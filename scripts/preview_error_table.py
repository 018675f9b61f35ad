#!/usr/bin/env python3
"""The split-sum error table of docs/PREVIEW.md ("The split-sum error at default settings"):
`brdfbake preview --env MAP --target T` (baked first with the target's settings), 512 x 512, the
default grid, for each map and target; per material group the median over its 12 roughnesses of the
spheres' relative RMS error in linear radiance (the worst sphere in brackets), and the reference's
bound on its worst sphere. Prints the Markdown tables.

    scripts/preview_error_table.py [--cli build/host/cli/brdfbake] [--maps ../shared/envmaps] [--out DIR]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

MAPS = ["venice_sunset_1k", "rooitou_park_1k", "studio_small_03_1k", "potsdamer_platz_1k"]
TARGETS = ["generic", "filament", "gltf", "babylon", "khronos-viewer"]
GROUPS = ["white", "grey", "dark", "gold", "copper", "silver"]


def percent(x):
    return "%.1f%%" % (100 * x) if x < 10 else "%.0f%%" % (100 * x)


def table(cli, map_path, out):
    rows = []
    for target in TARGETS:
        sheet = os.path.join(out, "%s_%s.png" % (os.path.basename(map_path).split(".")[0], target))
        subprocess.run([cli, "preview", "--env", map_path, "--target", target, "-o", sheet, "--quiet"], check=True)
        with open(sheet[:-4] + ".json") as f:
            doc = json.load(f)
        cells = []
        for group in GROUPS:
            errors = [s["error"]["linear"]["rms"] for s in doc["spheres"] if s["name"].split(" ")[0] == group]
            if len(errors) != 12:
                sys.exit("%s: %d spheres of %s (expected 12)" % (sheet, len(errors), group))
            cells.append("%s (%s)" % (percent(statistics.median(errors)), "%.0f%%" % (100 * max(errors))))
        bound = max(s["reference_bound"]["rms"] for s in doc["spheres"])
        rows.append("| `%s` | %s | %.2f%% |" % (target, " | ".join(cells), 100 * bound))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cli", default="build/host/cli/brdfbake")
    p.add_argument("--maps", default="../shared/envmaps")
    p.add_argument("--out", default="bench-out/preview_table")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for name in MAPS:
        path = os.path.join(a.maps, name + ".hdr")
        if not os.path.exists(path):
            sys.exit("no %s (the shared maps: ../shared/README.md)" % path)
        print("**%s** — split-sum vs reference, relative RMS per sphere: median over the 12 roughnesses (worst)\n" % name)
        print("| target | " + " | ".join(GROUPS) + " | reference bound (worst sphere) |")
        print("|---|" + "---:|" * (len(GROUPS) + 1))
        for row in table(a.cli, path, a.out):
            print(row)
        print(flush=True)


if __name__ == "__main__":
    main()
