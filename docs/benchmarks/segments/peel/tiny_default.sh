# Session 27: tiny scenes of the three families (the test fixture's generator arguments) trained at the tiny
# preset's own schedule (800 steps, 22k-26k Gaussians), then scripts/bench_segments.py with today's
# code and with the code in $BEFORE (a tree of the commit before fa6729a: `git archive fa6729a~1 | tar -x -C DIR`).
#   BEFORE=/tmp/before bash docs/benchmarks/segments/peel/tiny_default.sh WORK   (from the repository root)
set -u
W=$1; mkdir -p $W; REPO=$(pwd)
for f in livingroom statue tabletop; do
  S=$W/scene_$f
  [ -d $S ] || .venv-blender/bin/python scripts/make_scene.py --family $f --out $S --views 8 --res 96 --samples 4 \
    --seed 3 --points 3000 > $W/make_$f.log 2>&1
  [ -f $W/run_$f/metrics.json ] || PYTHONPATH=. .venv/bin/python -m engine train --scene $S --out $W/run_$f \
    --preset tiny --steps 800 --device cpu > $W/train_$f.log 2>&1
  grep -h '"psnr"\|"gaussians"' $W/run_$f/metrics.json | tr -d '\n'; echo " $f"
  .venv/bin/python scripts/bench_segments.py --run $W/run_$f --results $W/today > /dev/null 2>&1
  (cd $BEFORE && $REPO/.venv/bin/python scripts/bench_segments.py --run $W/run_$f --results $W/before > /dev/null 2>&1)
done
.venv/bin/python docs/benchmarks/segments/peel/summary.py $W/today $W/before
