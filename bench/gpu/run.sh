#!/usr/bin/env bash
# The OpenCL path and the benchmarks on a GPU machine, from the folder bench/gpu/bundle.sh made
# (docs/BENCHMARKS.md, "On an NVIDIA GPU"). Every step has its own time limit; the log says each
# step's wall time and exit code.
#   bash .gpu/run.sh [OUTDIR]
set -u
G=$(cd "$(dirname "$0")" && pwd) O=${1:-/tmp/gpuout}
mkdir -p "$O" && cd "$O" || exit 1
export LD_LIBRARY_PATH=$G/lib PATH=$G/bin:$PATH TIMEFORMAT='wall %R s (user %U, sys %S)'
if [[ -z ${OCL_ICD_VENDORS:-} ]]; then  # the NVIDIA driver's OpenCL library, wherever it is mounted
  lib=$(find /usr/local/nvidia /usr/lib /usr/lib64 /opt -name 'libnvidia-opencl.so*' 2> /dev/null | head -1)
  [[ -z $lib ]] && { echo "no NVIDIA OpenCL library found"; exit 3; }
  mkdir -p /tmp/ocl && echo "$lib" > /tmp/ocl/nvidia.icd && export OCL_ICD_VENDORS=/tmp/ocl
fi
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv 2>&1; nproc; uptime
step() { local t=$1; shift; echo; echo "=== [$t s] $*"; time timeout "$t" "$@"; echo "rc $?"; }
V=$G/shared/envmaps/venice_sunset_1k.hdr
step 30 brdfbake devices
# Each hot kernel against the device's measured peak (issue 36; docs/REPORT.md): in the device's own
# shape (gpu on a GPU), then in the CPU shape forced, for the comparison.
step 150 brdfbake report --kinds kernels -o kernels_auto.html
BRDFBAKE_KERNEL_SHAPE=cpu step 150 brdfbake report --kinds kernels -o kernels_cpu.html
# Agreement with the scalar double reference (on this machine's CPU): max |device - reference|.
for k in ggx ggx-multiscatter charlie; do
  for p in fp32 fp64; do step 60 brdfbake lut --kind $k --size 32 --precision $p -o lut_${k}_$p.csv --quiet; done
  step 120 brdfbake lut --kind $k --size 32 --device reference -o lut_${k}_ref.csv --quiet
done
python3 - << 'PY'
import csv
def rows(f):
    r = [x for x in csv.reader(open(f)) if x and not x[0].startswith('#')]
    return r[0], [[float(v) for v in x] for x in r[1:]]
for k in ["ggx", "ggx-multiscatter", "charlie"]:
    head, ref = rows(f"lut_{k}_ref.csv")
    for p in ["fp32", "fp64"]:
        _, dev = rows(f"lut_{k}_{p}.csv")
        worst = [max(abs(a[c] - b[c]) for a, b in zip(dev, ref)) for c in range(2, len(head))]
        print(f"agreement {k} {p}: max |device - reference| per channel {['%.2e' % w for w in worst]}")
PY
step 60 startup_stages lut 512
step 60 startup_stages irradiance "$V"
step 60 startup_stages prefilter "$V" 256
step 60 startup_stages prefilter "$V" 256 charlie
step 90 startup_stages prefilter "$V" 1024
# The kernel shapes (docs/DEVICES.md): the steps above run the GPU shape (auto on a GPU); the same
# chains in the CPU shape, the shape of the first H200 figures, for the comparison.
BRDFBAKE_KERNEL_SHAPE=cpu step 60 startup_stages prefilter "$V" 256
BRDFBAKE_KERNEL_SHAPE=cpu step 120 startup_stages prefilter "$V" 1024
for i in 1 2 3; do step 60 brdfbake preview --environment "$V" -o preview$i.png --quiet; done  # 1: cold caches
step 60 brdfbake bake --environment "$V" -o bake --quiet
for i in 1 2 3; do step 60 brdfbake preview --bake bake --environment "$V" -o splitsum$i.png --quiet --no-reference; done
python3 -c "
import json, glob
for f in sorted(glob.glob('*.json')):
    d = json.load(open(f)); print(f, json.dumps(d.get('times')))"
step 150 prefilter_bench --default-only --shared "$G/shared" --out prefilter
step 240 brdf_bench --quick --out brdf.md
step 100 bake_bench --scenes "$G/scenes" --env "$V" --reps 3 --out bake.md
step 100 lut_accuracy --quick --only-quadrature --out lutacc
step 40 fresnel_bench --quick --out fresnel.md
echo "=== done"; uptime
