# Session 27: tiny scenes of the three families (the test fixture's generator arguments) trained at the tiny
# preset's own schedule (800 steps, 22k-26k Gaussians), then scripts/bench_segments.py's measurement with today's
# code and with the code in $BEFORE (a tree of the commit before fa6729a: `git archive fa6729a~1 | tar -x -C DIR`).
#   BEFORE=/tmp/before bash docs/benchmarks/segments/peel/tiny_default.sh WORK   (from the repository root)
set -u
W=$1; mkdir -p $W; REPO=$(pwd)
cat > $W/measure.py <<'PY'
import sys, tempfile
from pathlib import Path
sys.path.insert(0, ".")
from scripts.bench_segments import measure
with tempfile.TemporaryDirectory() as tmp:
    r = measure(Path(sys.argv[1]), Path(tmp), Path(sys.argv[2]), 0.2)
a, m = r["auto"], r["masks"]
print("MEASURE", sys.argv[3], r["scene"], r["gaussians"], "proposals", a["proposals"], "target", a["target_iou"],
      "merges", a["merges"], a["objects"], "| masks", m["association"], m["target_iou"], flush=True)
PY
for f in livingroom statue tabletop; do
  S=$W/scene_$f
  [ -d $S ] || .venv-blender/bin/python scripts/make_scene.py --family $f --out $S --views 8 --res 96 --samples 4 \
    --seed 3 --points 3000 > $W/make_$f.log 2>&1
  [ -f $W/run_$f/metrics.json ] || PYTHONPATH=. .venv/bin/python -m engine train --scene $S --out $W/run_$f \
    --preset tiny --steps 800 --device cpu > $W/train_$f.log 2>&1
  grep -h '"psnr"\|"gaussians"' $W/run_$f/metrics.json | tr -d '\n'; echo " $f"
  PYTHONPATH=. .venv/bin/python $W/measure.py $W/run_$f $W/pic_today today 2>&1 | grep MEASURE
  (cd $BEFORE && PYTHONPATH=. $REPO/.venv/bin/python $W/measure.py $W/run_$f $W/pic_before before 2>&1 | grep MEASURE)
done
