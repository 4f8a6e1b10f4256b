#!/usr/bin/env bash
# VG's overhead over QB in executed instructions: the deterministic companion of
# `bench_simplify --vg-overhead`, whose CPU times move by several points from run to run on a
# shared machine. For each mesh: V once with `visimp visibility` (258 cameras, 480²), then one
# simplify() to 10% on one thread under callgrind for QB, VG with V = 1 (QB's collapse sequence: the engine's
# own cost) and VG with the real V. Only simplify() is counted (validation, set-up, collapses,
# extraction); reading the mesh and computing V are not. One thread: --toggle-collect counts
# only a thread with simplify() on its stack, so on two the worker's share of the parallel
# phase went uncounted, and that share moves with scheduling (the dragon's VG with V = 1,
# QB's own work, once counted 15.7% below QB). One thread runs the same lanes, same mesh.
#
# usage: bench/vg_overhead_instructions.sh [BUILD_DIR] [MESH.ply ...]
#   BUILD_DIR: a build with the benchmarks (default build/bench, `cmake --workflow --preset bench`)
#   meshes default to ../shared/meshes/{kicad_dsub62_male,fandisk_cad,dragon}.ply
# needs valgrind (.ci/install-deps installs it). About 2 minutes in all, most of it the dragon.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/bench}
shift || true
meshes=("$@")
if ((${#meshes[@]} == 0)); then
  meshes=(../shared/meshes/kicad_dsub62_male.ply ../shared/meshes/fandisk_cad.ply ../shared/meshes/dragon.ply)
fi
visimp=$build/apps/visimp
bench=$build/bench/bench_simplify
for tool in "$visimp" "$bench"; do
  [ -x "$tool" ] || { echo "vg_overhead_instructions: $tool not built (cmake --workflow --preset bench)" >&2; exit 1; }
done
command -v valgrind >/dev/null || { echo "vg_overhead_instructions: valgrind is not installed (.ci/install-deps)" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Instructions collected inside visimp::simplify() for one mode.
count() {
  valgrind --tool=callgrind --toggle-collect='visimp::simplify(*' --callgrind-out-file="$work/cg.out" \
    "$bench" --single-run "$1" "$2" 0.1 1 >"$work/run.txt" 2>"$work/cg.err"
  sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$work/cg.err"
}

echo "| mesh | QB instructions | VG (V = 1) | vs QB | VG (real V) | vs QB | refused collapses QB / VG |"
echo "|---|---|---|---|---|---|---|"
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .ply)
  "$visimp" visibility "$mesh" "$work/v.ply" >/dev/null
  qb=$(count qb "$work/v.ply"); qb_refused=$(sed -n 's/.*collapses, \([0-9]*\) refused/\1/p' "$work/run.txt")
  ones=$(count vg-ones "$work/v.ply")
  real=$(count vg "$work/v.ply"); vg_refused=$(sed -n 's/.*collapses, \([0-9]*\) refused/\1/p' "$work/run.txt")
  awk -v n="$name" -v q="$qb" -v o="$ones" -v r="$real" -v rq="$qb_refused" -v rv="$vg_refused" 'BEGIN {
    printf "| %s | %.1fM | %.1fM | %+.2f%% | %.1fM | %+.2f%% | %s / %s |\n",
           n, q / 1e6, o / 1e6, 100 * (o / q - 1), r / 1e6, 100 * (r / q - 1), rq, rv }'
done
