# wait up to $1 s for the detached benchmarks, show progress; when all are done write the report and pack it
export PYTHONPATH=/tmp/site SPLATFILL_ENGINE_PYTHON=$(command -v python3)
end=$(( $(date +%s) + $1 ))
while pgrep -f scripts/benchmark.py > /dev/null && [ $(date +%s) -lt $end ]; do sleep 15; done
for f in /tmp/b/*.log; do echo "== $f"; grep -v '^{' $f | tail -4; done
find /tmp/b/out/work -name stage_times.json -exec sh -c 'echo {}; cat {}' \;
ls /tmp/b/out/work/*/seed0/run/complete/ 2>/dev/null
if ! pgrep -f scripts/benchmark.py > /dev/null; then
  python3 scripts/benchmark.py --scenes $(ls -d /tmp/b/scenes/*) --methods init reference --inpainters telea exemplar --seeds 0 --out /tmp/b/out --perceptual l1 --report-only > /tmp/b/report.log 2>&1
  tail -3 /tmp/b/report.log
  cd /tmp/b/out && mkdir -p pack && for d in work/*/seed0/run; do n=$(basename $(dirname $(dirname $d))); mkdir -p pack/$n
    cp $d/metrics.json $d/removed/removal.json pack/$n/ 2>/dev/null; cp $d/removed/effects/effects.json pack/$n/ 2>/dev/null
    python3 -c "import json; d=json.load(open('$d/holes/holes.json')); d['views']=[v for v in d['views'] if 'iou_vs_truth' in v]; json.dump(d, open('pack/$n/holes.json','w'), indent=1)"
    for c in $d/complete/*/; do m=$(basename "$c"); cp "$c/scores.json" "pack/$n/${m}_scores.json" 2>/dev/null; cp "$c/scene/reference_fill.json" "pack/$n/${m}_reference_fill.json" 2>/dev/null; done
  done
  tar czf $OUT/full16.tgz pack results.json results.csv tables.md stability.md speed_accuracy.png pictures work/*/seed0/stage_times.json 2>/dev/null; ls -la $OUT
fi
