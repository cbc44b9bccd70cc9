#!/usr/bin/env bash
# The completion matrix of one scene on one GPU, as run for docs/benchmark/ (from the repository root):
#   bash docs/benchmark/run_scene.sh SCENE_DIR OUT [SECONDS] [SEEDS...]
# Runs the cells in order (seed by seed), stops after SECONDS (default 500), then --report-only writes the
# tables, chart and pictures from every cell that finished, and the log lists each stage's time. The
# engine's Python must be python3 on PATH. (Two seeds as two processes at once on one GPU were tried on
# statue and were slower per stage than one alone: the GPU time-slices between processes.)
set -u
scene=$1 out=$2 limit=${3:-500}
shift $(( $# < 3 ? $# : 3 ))
seeds=("${@:-0 1}")
common=(--scenes "$scene" --methods ft3 ftall init direct --inpainters telea exemplar --out "$out"
        --steps 3000 --max-gaussians 100000 --dilate 4 --perceptual l1 --device cuda)
export SPLATFILL_ENGINE_PYTHON=${SPLATFILL_ENGINE_PYTHON:-$(command -v python3)}
mkdir -p "$out"
start=$(date +%s)
timeout "$limit" python3 scripts/benchmark.py "${common[@]}" --seeds ${seeds[@]} 2>&1 | tee "$out/log.txt"
echo "matrix: $(( $(date +%s) - start )) s wall" | tee -a "$out/log.txt"
python3 scripts/benchmark.py "${common[@]}" --seeds ${seeds[@]} --report-only > "$out/log-report.txt" 2>&1
for f in "$out"/work/*/seed*/stage_times.json; do echo "$f"; cat "$f"; echo; done | tee -a "$out/log.txt"
