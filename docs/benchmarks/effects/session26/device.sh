# Session 26 (issue 16): removal patches judged through to the number the target reads, on one GPU. One livingroom_s0
# base run at the defaults; then for today's code and for today's with each patch of $PATCHES (NAME=PATH ...)
# applied, each in its own copy of the run and all at once:
# removal, hole masks, the exemplar inpainting, the Ref-exemplar cell (warm, 3,000 steps) and its scores. Into $OUT:
# score.py's judgement of the removals (judge.txt, judge.png), the base run's metrics.json, and per variant its
# removal.json, the cell's scores.json, the test views' renders (removed, Ref-exemplar) and the reference view's
# carried fill, for analysis here (renders.tgz).
#   carry .whl .bench/full_1:  PATCHES="a=x.patch b=y.patch" bash docs/benchmarks/effects/session26/device.sh
[ -n "$PATCHES" ] || { echo "device.sh: set PATCHES to NAME=PATH of the patches to judge (paths from the repository root)"; exit 2; }
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built /tmp/b/gsplat.log && break; sleep 5; done
S=/tmp/b/scenes/livingroom_s0; J=/tmp/j; mkdir -p $J
target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
[ -f $J/run/point_cloud.ply ] || python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 || { tail -5 $J/train.log; exit 1; }
V=today; for p in $PATCHES; do V="$V ${p%%=*}"
  rm -rf $J/code_${p%%=*} && cp -r . $J/code_${p%%=*} && patch -s -p1 -d $J/code_${p%%=*} < ${p#*=} || exit 1; done
chain() {  # $1: variant name, $2: code folder; everything in $J/$1 (a copy of the base run)
  local R=$J/$1 t=$(date +%s)
  [ -d $R ] || cp -r $J/run $R
  (cd $2 && export PYTHONPATH=/tmp/site:. &&
    python3 -m engine remove --run $R --object "$target" --device cuda &&
    python3 -m engine holes --run $R --device cuda &&
    python3 -m engine inpaint --run $R --inpainter exemplar &&
    python3 -m engine complete --run $R --method reference --inpainter exemplar --device cuda) > $J/$1.log 2>&1 ||
    tail -5 $J/$1.log
  echo "$1: $(( $(date +%s) - t )) s"
}
chain today . & for v in ${V#today }; do chain $v $J/code_$v & done; wait
python3 docs/benchmarks/effects/session23/score.py $S $(for v in $V; do echo $J/$v/removed; done) --picture $OUT/judge.png | tee $OUT/judge.txt
for v in $V; do
  c="$J/$v/complete/Ref-exemplar[warm]"
  python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(sys.argv[2], 'm-PSNR', round(s['scores']['m_psnr'], 3), 'unfilled', round(s['removed_scores']['m_psnr'], 3), 'PSNR', round(s['scores']['psnr'], 3))" "$c/scores.json" $v
done | tee -a $OUT/judge.txt
tests=$(python3 -c "import json; print(' '.join(json.load(open('$S/split.json'))['test']))")
(cd $J && tar czf $OUT/renders.tgz $(for v in $V; do c="$v/complete/Ref-exemplar[warm]"
  ref=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['reference'])" "$c/scene/reference_fill.json")
  echo "$c/scores.json" "$c/scene/reference_fill.json" "$c/scene/images/$ref" $v/removed/removal.json; for n in $tests; do echo $v/removed/images/$n "$c/renders/$n"; done
  done))
cp $J/run/metrics.json $OUT/ 2>/dev/null; tail -c 3000 $J/today.log > $OUT/today_tail.log; ls -la $OUT
