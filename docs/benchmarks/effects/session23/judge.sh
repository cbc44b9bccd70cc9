# The linear-light relight judged on a GPU removal (prepared in session 23, not yet run): one livingroom_s0 base run
# at the defaults, then its removal twice, today's code and today's with linear_relight.patch applied, scored by
# score.py against the scene's exact data (outside the hole, the effect's interior, edge and halves), with a
# picture of the first test view (srgb | linear | gt) into $JOUT (default $OUT). One call on one GPU, carry .whl
# .bench/full_1; about 450 s. Run 10 runs it in the background beside its matrices (../../full/run10/device.sh judge).
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built /tmp/b/gsplat.log && break; sleep 5; done
S=/tmp/b/scenes/livingroom_s0; J=/tmp/j; mkdir -p $J
target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
[ -f $J/run/point_cloud.ply ] || python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 || { tail -5 $J/train.log; exit 1; }
rm -rf $J/lin && cp -r . $J/lin && patch -s -p1 -d $J/lin < docs/benchmarks/effects/session23/linear_relight.patch || exit 1
[ -d $J/srgb ] || python3 -m engine remove --run $J/run --object "$target" --out $J/srgb --device cuda > $J/srgb.log 2>&1
[ -d $J/linear ] || (cd $J/lin && PYTHONPATH=/tmp/site:. python3 -m engine remove --run $J/run --object "$target" \
  --out $J/linear --device cuda > $J/linear.log 2>&1)
python3 docs/benchmarks/effects/session23/score.py $S $J/srgb $J/linear --picture ${JOUT:-$OUT}/judge.png | tee ${JOUT:-$OUT}/judge.txt
