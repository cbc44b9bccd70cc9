# The hole-mask stage before and after the visibility tests moved into ViewStack (ed54323), on one GPU machine:
# one livingroom_s0 training (10k steps: the masks' cost depends on the views, not on the steps), its removal, then
# `holes` three times on that run: the code before (69b43bb's engine, carried as .bench/oldengine: numpy, one view
# at a time), today's on the GPU (the default, auto) and today's on the CPU. The masks are compared pixel by pixel.
# carry: .whl .bench/full_1 .bench/oldengine.   Writes $OUT/view_stack.txt (records/: run once, session 23; ViewStack
# was then reverted in fe901a9, so on today's code the three runs are all the numpy loop).
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built /tmp/b/gsplat.log && break; sleep 5; done
S=/tmp/b/scenes/livingroom_s0; R=/tmp/h/run; T=$OUT/view_stack.txt; mkdir -p /tmp/h
target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
[ -f $R/point_cloud.ply ] || python3 -m engine train --scene $S --out $R --steps 10000 --device cuda > /tmp/h/train.log 2>&1 || { tail -5 /tmp/h/train.log; exit 1; }
python3 -m engine remove --run $R --object "$target" --device cuda > /tmp/h/remove.log 2>&1 || { tail -5 /tmp/h/remove.log; exit 1; }
nvidia-smi -L > $T; nproc >> $T
stage() { local name=$1; shift; local t0=$(date +%s.%N)
  "$@" > /tmp/h/$name.log 2>&1 || tail -3 /tmp/h/$name.log
  echo "$name: $(python3 -c "print(round($(date +%s.%N) - $t0, 1))") s (the whole command)" >> $T; }
stage before env PYTHONPATH=/tmp/site:.bench/oldengine python3 -m engine holes --run $R --out /tmp/h/holes_before
stage gpu python3 -m engine holes --run $R --out /tmp/h/holes_gpu
stage cpu python3 -m engine holes --run $R --out /tmp/h/holes_cpu --device cpu
python3 - >> $T <<'PY'
import json
from pathlib import Path
from engine.io.image_io import read_png
h = Path("/tmp/h"); before = h / "holes_before"
for other in ("holes_gpu", "holes_cpu"):
    for kind in (".", "unseen"):
        names = [p for p in sorted((before / kind).glob("*.png")) if p.name != "sheet.png"]
        diff = sum(int((read_png(p, "mask") != read_png(h / other / kind / p.name, "mask")).sum()) for p in names)
        px = sum(int((read_png(p, "mask") > 0).sum()) for p in names)
        print(f"{other} {'masks' if kind == '.' else kind}: {len(names)} views, {px} hole px before, {diff} px differ")
for name in ("holes_before", "holes_gpu", "holes_cpu"):
    r = json.loads((h / name / "holes.json").read_text())
    print(name, "unseen IoU", r["mean_unseen_iou_vs_truth"], "written IoU", r["mean_iou_vs_truth"])
PY
cat $T
