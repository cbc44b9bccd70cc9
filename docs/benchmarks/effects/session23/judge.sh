# A removal patch judged on a GPU removal: one livingroom_s0 base run at the defaults, then its removal twice, today's
# code and today's with $PATCH applied, scored by score.py against the scene's exact data (outside the hole, the
# effect's interior, edge and halves), with a picture of the first test view (today | patched | gt) into $JOUT
# (default $OUT). One call on one GPU, carry .whl .bench/full_1; about 450 s. Prepared in session 23 for
# linear_relight.patch (judged in run 11, applied in session 25); session 25 made the patch a parameter:
#   PATCH=docs/benchmarks/effects/session25/trimmed_mean.patch bash docs/benchmarks/effects/session23/judge.sh
[ -n "$PATCH" ] || { echo "judge.sh: set PATCH to the patch to judge (a path from the repository root)"; exit 2; }
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built /tmp/b/gsplat.log && break; sleep 5; done
S=/tmp/b/scenes/livingroom_s0; J=/tmp/j; mkdir -p $J
target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
[ -f $J/run/point_cloud.ply ] || python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 || { tail -5 $J/train.log; exit 1; }
rm -rf $J/patched_code && cp -r . $J/patched_code && patch -s -p1 -d $J/patched_code < $PATCH || exit 1
[ -d $J/today ] || python3 -m engine remove --run $J/run --object "$target" --out $J/today --device cuda > $J/today.log 2>&1
[ -d $J/patched ] || (cd $J/patched_code && PYTHONPATH=/tmp/site:. python3 -m engine remove --run $J/run \
  --object "$target" --out $J/patched --device cuda > $J/patched.log 2>&1)
python3 docs/benchmarks/effects/session23/score.py $S $J/today $J/patched --picture ${JOUT:-$OUT}/judge.png | tee ${JOUT:-$OUT}/judge.txt
