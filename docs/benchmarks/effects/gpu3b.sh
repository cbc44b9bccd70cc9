# call B (back to back, same machine): Init and Ref with exemplar at 10k steps, then pack results
export PYTHONPATH=/tmp/site
t() { local s=$(date +%s); "$@" > /tmp/r16/last-$$.log 2>&1; local rc=$?; echo "$(( $(date +%s) - s )) s rc=$rc: $*"; grep -v '^{' /tmp/r16/last-$$.log | tail -2; }
ls /tmp/r16 || exit 1
for name in livingroom statue; do
  for m in init reference; do
    ( t python3 -m engine complete --run /tmp/r16/run-$name --method $m --inpainter exemplar --steps 10000 --device cuda ) &
  done
done
wait
cd /tmp/r16 && mkdir -p pack && for name in livingroom statue; do R=run-$name; mkdir -p pack/$name
  cp $R/removed/removal.json $R/effects/effects.json pack/$name/
  python3 -c "import json; d=json.load(open('$R/holes/holes.json')); d['views']=[v for v in d['views'] if 'iou_vs_truth' in v]; json.dump(d, open('pack/$name/holes.json','w'), indent=1)"
  for c in $R/complete/*/; do m=$(basename "$c"); mkdir -p "pack/$name/$m"; cp "$c/scores.json" "pack/$name/$m/" 2>/dev/null; cp -r "$c/renders" "pack/$name/$m/" 2>/dev/null; cp "$c/scene/reference_fill.json" "pack/$name/$m/" 2>/dev/null; done
done
tar czf $OUT/r16e.tgz pack; ls -la $OUT
