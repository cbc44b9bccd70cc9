# On the device (issue 16, the tabletop's hole IoU): every call runs this. It installs what the call carries, unpacks
# the scenes whose parts have all come, and starts, detached, each new scene's base run at the defaults (30k steps,
# 300k budget, seed 0) on a GPU (two share one where there are more than four), then `remove`, `holes`, the rule
# before this session (holes_before.py) and, with DUMP=1, dump.py (the trained depths the hole rule reads, cropped round
# the object) into /tmp/b/r15. `bash base.sh pack` copies what has finished to $OUT. The first two chains ran the dump
# alone (the first on four scenes, before the object's own depth was added); the third, holes and holes_before.
#   A: carry .whl .gsplat_build .bench/r15a  (the short last parts of tabletop_s0, tabletop_s1, livingroom_s1, statue_s1)
#   B, C, D, E, F: carry .bench/r15b .. r15f (the rest of tabletop_s0, tabletop_s1, livingroom_s0, livingroom_s1;
#                 statue_s0 and the rest of statue_s1)
B=/tmp/b; W=$B/r15; mkdir -p $B/parts $B/scenes $W
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
if [ "$1" = pack ]; then
  for f in $W/*.npz; do cp $f $OUT/; done; tail -n 2 $W/*.log
  (cd $W && tar czf $OUT/records.tgz */metrics.json */removed/removal.json */removed/effects/effects.json \
    */holes/holes.json */holes_before/holes.json */holes/sheet.png */holes_before/sheet.png *.log 2>/dev/null); ls -la $OUT; exit 0
fi
[ -d .whl ] && [ ! -d /tmp/site/gsplat ] && python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site .whl/*.whl
bash docs/benchmarks/train/speed/gsplat_cached.sh > /dev/null
for d in .bench/r15*; do [ -d $d ] && cp $d/* $B/parts/; done
python3 docs/benchmarks/effects/run8/unpack.py $B/parts $B/scenes
[ -d $B/code ] || cp -r . $B/code
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1  # built once, before the runs
one() {  # scene, gpu
  local r=$W/$1 t; t=$(python3 -c "import json,sys; print([o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')][0])" $B/scenes/$1/masks/objects.json)
  export CUDA_VISIBLE_DEVICES=$2
  { python3 -m engine train --scene $B/scenes/$1 --out $r --device cuda && python3 -m engine remove --run $r --object $t --device cuda &&
    python3 -m engine holes --run $r && python3 docs/benchmarks/effects/run15/holes_before.py $r $r/holes_before &&
    { [ "$DUMP" = 1 ] && python3 docs/benchmarks/effects/run15/dump.py $r $W/$1.npz || touch $W/$1.done; }; } > $W/$1.log 2>&1
}
cd $B/code
for s in $(ls $B/scenes); do
  [ -e $W/$s.started ] && continue; [ -e $B/scenes/$s/.ready ] || continue
  g=$(( $(ls $W/*.started 2>/dev/null | wc -l) % 4 )); touch $W/$s.started
  (setsid nohup bash -c "$(declare -f one); W=$W B=$B; one $s $g" > /dev/null 2>&1 < /dev/null &)
  echo "started $s on GPU $g"
done
sleep 5; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv,noheader
