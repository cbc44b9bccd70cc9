#!/usr/bin/env bash
# Objects without masks on the GPU machine (from the repository root, engine Python as python3):
#   bash docs/benchmarks/segments/run_gpu.sh RUNS RESULTS SCENE...
# Trains the generated scenes side by side on the one GPU (30k steps, 100k-Gaussian budget; three at once
# went about three times faster in all than one after another) into RUNS, skipping a run already there;
# as each finishes, scripts/bench_segments.py hides that scene's masks and scores `segment --auto` and
# `--from-masks` with perturbed masks; records land in RESULTS.
set -u
runs=$1 results=$2; shift 2
mkdir -p "$runs" "$results"
python3 -c "from gsplat.cuda._backend import _C" || exit 1  # build gsplat once, before the runs share it
for scene in "$@"; do
  name=$(basename "$scene")
  (
    [ -f "$runs/$name/metrics.json" ] || python3 -m engine train --scene "$scene" --out "$runs/$name" \
      --max-gaussians 100000 --device cuda > "$runs/train-$name.log" 2>&1
    tail -1 "$runs/train-$name.log"
    python3 scripts/bench_segments.py --run "$runs/$name" --results "$results" 2>&1 | tail -1
  ) &
done
wait
