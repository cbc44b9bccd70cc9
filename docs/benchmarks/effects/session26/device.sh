# Session 26 (issue 16): removal patches judged through to the number the target reads, on one GPU. One livingroom_s0
# base run at the defaults; then for today's code and for today's with each patch of $PATCHES (NAME=PATH ...)
# applied, each in its own copy of the run and all at once:
# removal, hole masks, the exemplar inpainting, the Ref-exemplar cell (warm, 3,000 steps) and its scores. Into $OUT:
# score.py's judgement of the removals (judge.txt, judge.png), the base run's metrics.json, and per variant its
# removal.json, the cell's scores.json, the test views' renders (removed, Ref-exemplar) and the reference view's
# carried fill, for analysis here (renders.tgz).
#   carry .whl .bench/full_1:  PATCHES="a=x.patch b=y.patch" bash docs/benchmarks/effects/session26/device.sh
# (medians.patch: 83c2f08 undone in engine/, so that "today" is the trimmed means and "medians" the code before)
# SCENE (default livingroom_s0) picks the scene, its work in /tmp/j/$SCENE; TRAIN_ONLY=1 receives what the call
# carries and starts that scene's base run in the background, for a later call (one carrying the next scene) to judge.
[ -n "$PATCHES" ] || [ -n "$TRAIN_ONLY" ] || { echo "device.sh: set PATCHES to NAME=PATH of the patches to judge (paths from the repository root)"; exit 2; }
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built /tmp/b/gsplat.log && break; sleep 5; done
S=/tmp/b/scenes/${SCENE:=livingroom_s0}; J=/tmp/j/$SCENE; mkdir -p $J
target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
if [ -n "$TRAIN_ONLY" ]; then  # setsid: the call returns while it trains
  [ -e $J/train.log ] || setsid nohup python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 < /dev/null &
  sleep 2; tail -n 1 $J/train.log; exit 0
fi
while pgrep -f "[e]ngine train --scene $S " > /dev/null; do sleep 5; done
[ -f $J/run/point_cloud.ply ] || python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 || { tail -5 $J/train.log; exit 1; }
V=today; for p in $PATCHES; do V="$V ${p%%=*}"
  rm -rf $J/code_${p%%=*} && cp -r . $J/code_${p%%=*} && patch -s -p1 -d $J/code_${p%%=*} < ${p#*=} || exit 1; done
chain() {  # $1: variant name, $2: code folder; everything in $J/$1 (a copy of the base run)
  local R=$J/$1 t=$(date +%s)
  [ -d $R ] || cp -r $J/run $R
  (cd $2 && export PYTHONPATH=/tmp/site:. &&
    python3 -m engine remove --run $R --object "$target" --device cuda &&
    python3 -m engine holes --run $R &&
    python3 -m engine inpaint --run $R --inpainter exemplar &&
    python3 -m engine complete --run $R --method reference --inpainter exemplar --device cuda) > $J/$1.log 2>&1 ||
    tail -5 $J/$1.log
  echo "$1: $(( $(date +%s) - t )) s"
}
chain today . & for v in ${V#today }; do chain $v $J/code_$v & done; wait
python3 docs/benchmarks/effects/session23/score.py $S $(for v in $V; do echo $J/$v/removed; done) --picture $OUT/${SCENE}_judge.png | tee $OUT/${SCENE}_judge.txt
for v in $V; do
  c="$J/$v/complete/Ref-exemplar[warm]"
  python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(sys.argv[2], 'm-PSNR', round(s['scores']['m_psnr'], 3), 'unfilled', round(s['removed_scores']['m_psnr'], 3), 'PSNR', round(s['scores']['psnr'], 3))" "$c/scores.json" $v
done | tee -a $OUT/${SCENE}_judge.txt
tests=$(python3 -c "import json; print(' '.join(json.load(open('$S/split.json'))['test']))")
for v in $V; do c="$v/complete/Ref-exemplar[warm]"  # one archive a variant: a file comes back only under 16 MiB
  ref=$(cd $J && python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['reference'])" "$c/scene/reference_fill.json")
  (cd $J && tar czf $OUT/${SCENE}_$v.tgz "$c/scores.json" "$c/scene/reference_fill.json" "$c/scene/images/$ref" \
    $v/removed/removal.json $(for n in $tests; do echo $v/removed/images/$n "$c/renders/$n"; done))
done
cp $J/run/metrics.json $OUT/${SCENE}_metrics.json 2>/dev/null; ls -la $OUT
