#!/usr/bin/env bash
# The completion matrix of one scene on one GPU, as run for docs/benchmark/ (from the repository root):
#   bash docs/benchmark/run_scene.sh SCENE_DIR OUT [SECONDS]
# Each seed runs as its own benchmark process, both at once on the one GPU (they share OUT; their work
# folders differ), each stopped after SECONDS (default 480); then --report-only writes the tables, chart
# and pictures from every cell that finished. The engine's Python must be python3 on PATH.
set -u
scene=$1 out=$2 limit=${3:-480}
common=(--scenes "$scene" --methods ft3 ftall init direct --inpainters telea exemplar --out "$out"
        --steps 3000 --max-gaussians 100000 --dilate 4 --perceptual l1 --device cuda)
export SPLATFILL_ENGINE_PYTHON=${SPLATFILL_ENGINE_PYTHON:-$(command -v python3)} OMP_NUM_THREADS=8
mkdir -p "$out"
start=$(date +%s)
for seed in 0 1; do
    timeout "$limit" python3 scripts/benchmark.py "${common[@]}" --seeds "$seed" > "$out/log-seed$seed.txt" 2>&1 &
done
wait
echo "both seeds: $(( $(date +%s) - start )) s wall" | tee "$out/wall.txt"
python3 scripts/benchmark.py "${common[@]}" --seeds 0 1 --report-only > "$out/log-report.txt" 2>&1
tail -n 3 "$out"/log-*.txt
