# on the device, in the last minutes of device time: train statue s0 at 640 (15k steps: a diagnosis, not a
# benchmark number), remove the statue and run ghost.py; each call adds the parts it carries (.bench/c) and
# the test views' gt_depth/ (.bench/c/gt_depth), and starts the detached job once the scene is whole
B=/tmp/b; S=$B/scenes/statue_s0; mkdir -p $B/parts $B/scenes
[ -d /tmp/site/gsplat ] || python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
cp .bench/c/*.tgz.* $B/parts/ 2>/dev/null; python3 docs/benchmarks/effects/run8/unpack.py $B/parts $B/scenes
[ -d .bench/c/gt_depth ] && cp -r .bench/c/gt_depth $B/
[ -d $B/code ] || cp -r . $B/code
if [ -e $S/.ready ] && [ -d $B/gt_depth ] && [ ! -e $B/started ]; then
  touch $B/started; cp -r $B/gt_depth $S/
  (cd $B/code && setsid nohup bash -c "python3 -m engine train --scene $S --out $B/run --seed 0 --steps 15000 --device cuda > $B/train.log 2>&1 &&
    python3 -m engine remove --run $B/run --object statue --device cuda > $B/remove.log 2>&1 &&
    python3 docs/benchmarks/effects/run9/ghost.py $B/run statue $B/ghost.json > $B/ghost.log 2>&1; touch $B/done" > /dev/null 2>&1 < /dev/null &)
fi
sleep 2; ls $B; tail -2 $B/train.log 2>/dev/null
