#!/usr/bin/env bash
# The walkthrough-LOD study (docs/cells.md): the shape of the paper's Tables 2 and 3 on 2M-,
# 4M- and 8M-face statuary parks built from our meshes, with and without projective textures,
# the prefetching runs of its Fig. 9, and the Ts / Tl / cell-size sweeps.
#
#   bench/cells_study.sh [OUT_DIR] [VISIMP]      (defaults: build/cells_study, build/release/apps/visimp)
#
# Needs ../shared/meshes (the dragon and the KiCad parts). About an hour on 2 cores, most of it
# building the 8M park's cells; the cell directories are removed once walked (~0.7 GB each).
# Writes OUT_DIR/study.csv, study.json, *.svg and index.html (bench/cells_study.py).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/build/cells_study}"
visimp="${2:-$root/build/release/apps/visimp}"
shared="$root/../shared/meshes"
meshes="$root/meshes"
[ -f "$shared/dragon.ply" ] || { echo "cells_study: needs $shared/dragon.ply" >&2; exit 1; }
mkdir -p "$out/runs"
cd "$out"

# The paper's dragon has 202,520 polygons; ours is decimated to that (visimp QB).
[ -f dragon202k.ply ] || "$visimp" simplify "$shared/dragon.ply" dragon202k.ply --target 202520 >/dev/null
# Heavy meshes once, light ones twice, so the parks average ~32k faces an object like the paper's.
list="$out/dragon202k.ply,$shared/kicad_dsub62_male.ply:z,$shared/kicad_cap_snapin_d40.ply:z"
list="$list,$meshes/kicad_esp_wroom02.ply:z,$meshes/fandisk_cad.ply,$meshes/teapot.ply,$meshes/bunny.ply"
list="$list,$meshes/teapot.ply,$meshes/bunny.ply,$meshes/fandisk_cad.ply,$meshes/kicad_esp_wroom02.ply:z"

run_config() {  # NAME PARK CELL TS TL [build flags...]
  local name=$1 park=$2 cell=$3 ts=$4 tl=$5
  shift 5
  local dir="cells_$name"
  echo "== $name: build" >&2
  "$visimp" cells build "park$park.json" -o "$dir" --cell-size "$cell" --ts "$ts" --tl "$tl" "$@" --json \
    >"runs/$name.build.json"
  echo "== $name: walk" >&2
  "$visimp" cells walk "park$park.json" "$dir" --path auto --frames 400 --reference-every 2 -o "runs/$name.walk" \
    --json >"runs/$name.walk.json"
  "$visimp" cells walk "park$park.json" "$dir" --path auto --frames 400 --reference-every 2 --textures off \
    --json >"runs/$name.walk_plain.json"
}

for size in 2 4 8; do
  "$visimp" scene park -o "park${size}M.json" --faces "${size}000000" --area 1650,2035 --object-size 50 \
    --seed 7 --meshes "$list" >/dev/null
done

# Tables 2 and 3: every cell of each park, the paper's setting 50-5-4.5.
for size in 2 4 8; do
  run_config "${size}M-50-5-4.5" "${size}M" 50 5 4.5
  if [ "$size" = 4 ]; then
    # Fig. 9: frame times around cell crossings, prefetching on and off, cold and warm page cache.
    for prefetch in on off; do
      for cache in cold warm; do
        "$visimp" cells walk park4M.json "cells_4M-50-5-4.5" --path auto --frames 1200 --reference-every 0 \
          --prefetch "$prefetch" --cache "$cache" -o "runs/prefetch_${prefetch}_${cache}.walk" --json \
          >"runs/prefetch_${prefetch}_${cache}.json"
      done
    done
  fi
  rm -rf "cells_${size}M-50-5-4.5"
done

# visimp's default Tl (3: the paper's smallest; 4.5 misses 35 dB untextured) on every 4M cell.
run_config "4M-50-5-3.0-all" 4M 50 5 3.0
rm -rf "cells_4M-50-5-3.0-all"

# Sweeps on the 4M park (the cells along the walk and their neighbours only).
for cfg in "50 3 4.5" "50 7 4.5" "50 5 3.0" "50 5 6.0" "100 5 4.5"; do
  set -- $cfg
  run_config "4M-$1-$2-$3" 4M "$1" "$2" "$3" --path auto --frames 400
  rm -rf "cells_4M-$1-$2-$3"
done

python3 "$root/bench/cells_study.py" "$out"
echo "cells_study: $out/index.html" >&2
