#!/usr/bin/env bash
# Runs the ```sh blocks of docs/SERVICE.md, in order and exactly as written, in a fresh folder with
# the built brdfbake first on PATH; then checks what they left. Bounded: the whole run is stopped
# after 150 s, and the server the blocks start is killed whatever happens.
# usage: service_doc_test.sh docs/SERVICE.md path/to/brdfbake
set -euo pipefail
doc=$(realpath "$1")
cli=$(realpath "$2")
for tool in curl jq; do
  command -v "$tool" >/dev/null || { echo "service_doc: $tool is not installed (scripts/deps.sh installs it)"; exit 1; }
done
work=$(mktemp -d -t brdfbake-service-doc.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin"
ln -s "$cli" "$work/bin/brdfbake"
# The blocks, one script; a trap ends the server if a block fails before it is stopped.
{
  echo 'set -euo pipefail'
  echo 'trap '"'"'[ -n "${SERVER:-}" ] && kill -KILL "$SERVER" 2>/dev/null || true'"'"' EXIT'
  awk '/^```sh$/ {on = 1; next} /^```/ {on = 0} on' "$doc"
} > "$work/doc.sh"
blocks=$(grep -c '^```sh$' "$doc")
echo "service_doc: running $blocks blocks ($(grep -vc '^\s*$' "$work/doc.sh") lines) from $doc"
cd "$work"
PATH="$work/bin:$PATH" timeout 150 bash "$work/doc.sh" > doc.out 2>&1 || { cat doc.out; echo "service_doc: the commands failed"; exit 1; }
cat doc.out
# What a reader was promised: the default bake's files, the job's table, the fast path's table,
# the command line's downloads, a clean stop.
fail=0
for f in out/manifest.json out/dfg_ggx_multiscatter_128.exr out/prefilter_ggx_256.ktx2 out/irradiance_sh3.json \
         fresnel.csv dfg_ggx_128.exr from-server/manifest.json from-server/fresnel.csv from-server/sheen.exr \
         bake-from-server/manifest.json bake-from-server/prefilter_ggx_64.ktx2; do
  [ -s "$f" ] || { echo "service_doc: missing $f"; fail=1; }
done
grep -q '^done$' doc.out || { echo "service_doc: no job reported done"; fail=1; }
jq -e '.files | length == 3' out/manifest.json >/dev/null || { echo "service_doc: out/manifest.json does not list 3 files"; fail=1; }
cmp -s fresnel.csv from-server/fresnel.csv || { echo "service_doc: the two downloads of fresnel.csv differ"; fail=1; }
grep -q 'stopped' doc.out || { echo "service_doc: the server did not report a clean stop"; fail=1; }
[ "$fail" = 0 ] && echo "service_doc: 1 passed, 0 failed" || { echo "service_doc: 0 passed, 1 failed"; exit 1; }
