#!/usr/bin/env bash
# Regenerates the parts of the docs that the tool itself prints (tests check they are current):
# docs/SCENES.md's parameter table from `brdfbake kinds --markdown`.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cli=${1:-build/host/cli/brdfbake}
python3 - "$cli" <<'PY'
import subprocess, sys
cli = sys.argv[1]
table = subprocess.run([cli, "kinds", "--markdown"], check=True, capture_output=True, text=True).stdout
path = "docs/SCENES.md"
text = open(path).read()
begin, end = "<!-- kinds:begin -->\n", "<!-- kinds:end -->"
a, b = text.index(begin) + len(begin), text.index(end)
open(path, "w").write(text[:a] + table + text[b:])
PY
