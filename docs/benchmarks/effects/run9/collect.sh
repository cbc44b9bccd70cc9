# on the device: wait up to $1 s for the runner, then pack every finished record into $OUT: the JSON records and
# tables in one file with our hole and effect masks, the scenes' sheets at a third of their size and their methods'
# pictures at half size in another (a call returns files of at most 16 MiB)
# ($RUNNER: the folder whose runner.sh to start and wait for, run9 unless given; run10 spreads it over GPUs)
B=/tmp/b; end=$(( $(date +%s) + $1 ))
while pgrep -f "${RUNNER:-run9}/[r]unner.sh" > /dev/null && [ $(date +%s) -lt $end ]; do sleep 10; done
cat $B/runner*.log; export PYTHONPATH=/tmp/site:. SPLATFILL_ENGINE_PYTHON=$(command -v python3)
cd $B/code && python3 scripts/benchmark.py --scenes $(ls -d $B/scenes/*/ 2>/dev/null) --methods ${METHODS:-init reference} --inpainters ${INPAINTERS:-exemplar} \
  --seeds ${SEED:-0} --out $B/out --perceptual ${PERCEPTUAL:-l1} --report-only > $B/report.log 2>&1; tail -2 $B/report.log
cd $B/out && rm -rf pack sheets && mkdir pack sheets && for d in work/*/seed${SEED:-0}/run; do n=$(basename $(dirname $(dirname $d))); mkdir -p pack/$n sheets/$n
  cp $d/metrics.json $d/removed/removal.json $d/../stage_times.json $d/holes/holes.json $d/removed/effects/effects.json pack/$n/ 2>/dev/null
  for k in removed:removed/sheet.png holes:holes/sheet.png effects:removed/effects/sheet.png; do  # a third of their size
    python3 -c "import cv2,sys; i=cv2.imread(sys.argv[1]); cv2.imwrite(sys.argv[2], cv2.resize(i, None, fx=1/3, fy=1/3, interpolation=cv2.INTER_AREA))" $d/${k#*:} sheets/$n/${k%%:*}_sheet.png; done
  PYTHONPATH=/tmp/site:$B/code python3 $B/code/docs/benchmarks/effects/run15/breakdown.py $B/scenes/$n $d/removed > pack/$n/breakdown.txt  # where the error outside the true hole sits
  mkdir -p pack/$n/holes pack/$n/unseen pack/$n/effects sheets/$n/removed; for v in $(python3 -c "import json,sys; print(*json.load(open(sys.argv[1]))['test'])" $B/scenes/$n/split.json); do
    cp $d/holes/$v pack/$n/holes/; cp $d/holes/unseen/$v pack/$n/unseen/ 2>/dev/null; cp $d/removed/effects/$v pack/$n/effects/; done  # the test views' masks: all 100 would pass 16 MiB
  for v in $(python3 -c "import json,sys; print(*json.load(open(sys.argv[1]))['test'][:5])" $B/scenes/$n/split.json); do
    cp $d/removed/images/$v sheets/$n/removed/; done  # five removed test views at full size (2-2.5 MB), for breakdown.py here
  [ -f pictures/$n.png ] && python3 -c "import cv2,sys; i=cv2.imread(sys.argv[1]); cv2.imwrite(sys.argv[2], cv2.resize(i, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA))" pictures/$n.png sheets/$n/methods_half.png
  for c in $d/complete/*/; do m=$(basename "$c"); cp "$c/scores.json" "pack/$n/${m}_scores.json" 2>/dev/null; cp "$c/scene/reference_fill.json" "pack/$n/${m}_reference_fill.json" 2>/dev/null; done
done 2>/dev/null
for n in $(ls sheets); do tar czf $OUT/sheets_$n.tgz sheets/$n; done  # one file a scene: three scenes' passed 16 MiB together
tar czf $OUT/records.tgz pack results.json results.csv tables.md stability.md 2>/dev/null
tar czf $OUT/logs.tgz -C $B $(cd $B; ls runner*.log log_* bench_*.log 2>/dev/null)
for f in $OUT/*; do [ $(stat -c %s $f) -gt 16000000 ] && { echo "too big, dropped: $f"; rm $f; }; done; ls -la $OUT
