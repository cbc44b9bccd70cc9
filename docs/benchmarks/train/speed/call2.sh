# Issue 17 item 2, second device call: the host-side savings (adam_step, gsplat's SH kernel, the photometric
# loss's written-out gradient) against the code before them (.bench/old: `git archive 5fff953 engine scripts`),
# each from scratch to step 7000 (growing to 300k Gaussians), then from the old code's state at step 7000, alternating old and new twice; then the
# rasterizer check (SH now gsplat's on CUDA) and one full 30k-step training at the defaults.
# Carry .bench/w (wheels), .bench/p1 (scene parts), .gsplat_build, .bench/old.
python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site .bench/w/*.whl
export PYTHONPATH=/tmp/site:.
bash docs/benchmarks/train/speed/gsplat_cached.sh
mkdir -p /tmp/parts /tmp/scenes && cp .bench/p1/* /tmp/parts/ && python3 docs/benchmarks/effects/run8/unpack.py /tmp/parts /tmp/scenes
S=/tmp/scenes/livingroom_s0
/usr/bin/time -f "gsplat import %e s" python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()"
python3 scripts/check_rasterizer.py --scene $S --out $OUT/check_rasterizer.json > /dev/null 2>&1; echo check rc=$?
PYTHONPATH=/tmp/site:.bench/old python3 docs/benchmarks/train/speed/train_to.py $S 7000 /tmp/r7000 2>&1 | tail -2
python3 scripts/profile_train.py --scene $S --until 7000 --steps 500 --json $OUT/new_from_scratch.json > $OUT/new_from_scratch.log 2>&1
grep "trained to" $OUT/new_from_scratch.log
for i in 1 2; do
  PYTHONPATH=/tmp/site:.bench/old python3 .bench/old/scripts/profile_train.py --run /tmp/r7000 --steps 500 > $OUT/old_$i.log 2>&1
  grep "ms/step" $OUT/old_$i.log
  python3 scripts/profile_train.py --run /tmp/r7000 --steps 500 --json $OUT/new_$i.json > $OUT/new_$i.log 2>&1
  grep ms_per_step $OUT/new_$i.json
done
python3 scripts/bench_train.py --scenes $S --budgets 300000 --results $OUT/train > $OUT/train.log 2>&1; tail -5 $OUT/train.log
