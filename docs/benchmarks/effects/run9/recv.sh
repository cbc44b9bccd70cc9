# issue 16 at 640x480/100 views (ninth trainings), on the device: take this call's scene parts (.bench/c), install the wheels
# once, unpack every scene whose parts are all here, and start the runner once (it outlives the call)
# ($RUNNER: the folder whose runner.sh to start and wait for, run9 unless given; run10 spreads it over GPUs; none
# starts nothing, for a caller that starts its own, as docs/benchmarks/budget/curve.sh)
B=/tmp/b; mkdir -p $B/parts $B/scenes
[ -d /tmp/site/gsplat ] || python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null
export PYTHONPATH=/tmp/site
# gsplat's CUDA extension built on an earlier machine (run12/gsplat_build.sh; carry .gsplat_build): 5 s, not 77
bash docs/benchmarks/train/speed/gsplat_cached.sh
cp .bench/c/* $B/parts/ 2>/dev/null; rm -rf .bench/c
python3 docs/benchmarks/effects/run8/unpack.py $B/parts $B/scenes
[ -d $B/code ] || cp -r . $B/code   # the runner reads its own copy: later calls replace the tree
[ "$RUNNER" = none ] || pgrep -f "${RUNNER:-run9}/[r]unner.sh" > /dev/null || (cd $B/code && setsid nohup bash docs/benchmarks/effects/${RUNNER:-run9}/runner.sh "$@" > $B/runner.log 2>&1 < /dev/null &)
sleep 2; ls $B/scenes; tail -3 $B/runner.log; du -sh $B/parts
