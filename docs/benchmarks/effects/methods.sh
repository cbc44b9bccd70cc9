# Call B, back to back on the same machine: the completions at 10k steps, side by side, then pack the records:
#   bash methods.sh INPAINTER METHOD...   (third run: telea init reference ft direct, then exemplar init reference)
export PYTHONPATH=/tmp/site
inpainter=$1; shift
t() { local s=$(date +%s); "$@" > /tmp/r16/last-$$.log 2>&1; local rc=$?; echo "$(( $(date +%s) - s )) s rc=$rc: $*"; grep -v '^{' /tmp/r16/last-$$.log | tail -2; }
ls /tmp/r16 || exit 1
for name in livingroom statue; do  # this inpainter's fills, if stages.sh made another's
  [ -d /tmp/r16/run-$name/inpainted/$inpainter ] || t python3 -m engine inpaint --run /tmp/r16/run-$name --inpainter $inpainter
done
for name in livingroom statue; do
  for m in "$@"; do  # FT's perceptual term: no LPIPS weights offline, so L1 (the results say [l1])
    extra=""; [ "$m" = ft ] && extra="--perceptual l1"
    ( t python3 -m engine complete --run /tmp/r16/run-$name --method $m --inpainter $inpainter --steps 10000 --device cuda $extra ) &
  done
done
wait
cd /tmp/r16 && mkdir -p pack && for name in livingroom statue; do R=run-$name; mkdir -p pack/$name
  cp $R/metrics.json $R/removed/removal.json $R/removed/effects/effects.json pack/$name/
  cp $R/removed/effects/sheet.png pack/$name/effects_sheet.png; cp $R/holes/sheet.png pack/$name/holes_sheet.png
  python3 -c "import json; d=json.load(open('$R/holes/holes.json')); d['views']=[v for v in d['views'] if 'iou_vs_truth' in v]; json.dump(d, open('pack/$name/holes.json','w'), indent=1)"
  for c in $R/complete/*/; do m=$(basename "$c"); mkdir -p "pack/$name/$m"; cp "$c/scores.json" "pack/$name/$m/"; cp -r "$c/renders" "pack/$name/$m/"; cp "$c/scene/reference_fill.json" "pack/$name/$m/" 2>/dev/null; done
  mkdir -p pack/$name/removed_test pack/$name/effects_test pack/$name/holes_test
  for v in $(python3 -c "import json; print(' '.join(json.load(open('$name/split.json'))['test']))"); do cp $R/removed/images/$v pack/$name/removed_test/; cp $R/removed/effects/$v pack/$name/effects_test/; cp $R/holes/$v pack/$name/holes_test/; done
done
tar czf $OUT/r16-$inpainter.tgz pack; ls -la $OUT
