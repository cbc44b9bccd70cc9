# On the device: wait up to $1 s for device.sh's two benchmarks, then run overshoot.py on each finished base run
# (once) and pack the records (results, stage times, each cell's scores, removal and effects reports, overshoot.txt)
# into one file, $OUT/records16.tgz (a call returns at most eight).
B=/tmp/b; end=$(( $(date +%s) + $1 ))
while pgrep -f "[s]cripts/benchmark.py --scenes" > /dev/null && [ $(date +%s) -lt $end ]; do sleep 10; done
export PYTHONPATH=/tmp/site:$B/code; tail -3 $B/r16_*.log; P=/tmp/r16; rm -rf $P
for s in ${SCENES:-livingroom_s0 statue_s0}; do d=$B/out16_$s/work/$s/seed0; mkdir -p $P/$s; obj=$(python3 -c "import json,sys; print([o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')][0])" $B/scenes/$s/masks/objects.json)
  [ -f $d/run/removed/removal.json ] && [ ! -f $d/overshoot.txt ] && python3 $B/code/docs/benchmarks/effects/run16/overshoot.py $d/run $obj --device cuda > $d/overshoot.txt 2>&1
  cp $d/overshoot.txt $d/stage_times.json $d/run/metrics.json $d/run/removed/removal.json $d/run/removed/effects/effects.json $P/$s/ 2>/dev/null
  for c in $d/run/complete/*/; do cp "$c/scores.json" "$P/$s/$(basename "$c")_scores.json" 2>/dev/null; done
  cp $B/out16_$s/results.json $B/out16_$s/tables.md $P/$s/ 2>/dev/null; cat $d/overshoot.txt 2>/dev/null | tail -16
  [ -f $B/out16_$s/pictures/$s.png ] && python3 -c "import cv2,sys; i=cv2.imread(sys.argv[1]); cv2.imwrite(sys.argv[2], cv2.resize(i, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA), [cv2.IMWRITE_JPEG_QUALITY, 80])" $B/out16_$s/pictures/$s.png $P/$s/methods_half.jpg
done; cp $B/r16_*.log /tmp/om/others_margin.txt $P/ 2>/dev/null; tar czf $OUT/records16.tgz -C /tmp r16; ls -la $OUT
