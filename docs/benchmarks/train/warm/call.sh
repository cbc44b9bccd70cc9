# Issue 17 item 2, Init --warm on the GPU (one device call): statue_s0 (640x480, 100 views), base run at the defaults
# (30k steps, 300k budget), removal, holes, exemplar, then Init-warm at its default steps (a tenth of the base
# run's: 3,000) and Init from scratch at 10k steps (the benchmark's completions). Carry .whl, .gsplat_build,
# .bench/p2 (statue_s0's parts). About 9 min on an H200: give it the full 600 s limit (the first try, with 487 s of
# device time left, was cut before the from-scratch Init).
python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site .whl/*.whl
export PYTHONPATH=/tmp/site:. SPLATFILL_ENGINE_PYTHON=$(command -v python3)
bash docs/benchmarks/train/speed/gsplat_cached.sh
mkdir -p /tmp/parts /tmp/scenes && cp .bench/p2/* /tmp/parts/ && python3 docs/benchmarks/effects/run8/unpack.py /tmp/parts /tmp/scenes
S=/tmp/scenes/statue_s0; O=/tmp/o; common="--scenes $S --inpainters exemplar --seeds 0 --out $O --perceptual l1 --device cuda"
keep() {  # copy what has finished after each cell, so a call cut by its limit still brings back the times
  cp $O/results.json $O/tables.md $O/work/statue_s0/seed0/stage_times.json $O/work/statue_s0/seed0/run/metrics.json $OUT/ 2>/dev/null
  for c in $O/work/statue_s0/seed0/run/complete/*/; do cp "$c/scores.json" "$OUT/$(basename "$c")_scores.json" 2>/dev/null; done
}
python3 scripts/benchmark.py $common --methods init-warm > $OUT/warm.log 2>&1; tail -2 $OUT/warm.log; keep
python3 scripts/benchmark.py $common --methods init --complete-steps 10000 > $OUT/init.log 2>&1; tail -2 $OUT/init.log; keep
python3 scripts/benchmark.py $common --methods init init-warm --report-only > /dev/null 2>&1; keep
