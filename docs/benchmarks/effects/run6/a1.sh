# session 4, call 1: train tabletop at the defaults, remove, hole variants, dump for CPU diagnosis
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null; export PYTHONPATH=/tmp/site:.
export PYTHONUNBUFFERED=1
S=$1; OBJ=$2; OUT=/tmp/r/out; mkdir -p $OUT
mkdir -p /tmp/r; cp -r .bench/$S /tmp/r/scene_$S
t0=$(date +%s)
python3 -m engine train --scene /tmp/r/scene_$S --out /tmp/r/$S --device cuda > /tmp/r/$S-train.log 2>&1 || { tail -5 /tmp/r/$S-train.log; echo done-failed; exit 1; }
echo "trained $S in $(( $(date +%s) - t0 )) s"; tail -c 400 /tmp/r/$S/metrics.json
python3 -m engine remove --run /tmp/r/$S --object $OBJ --device cuda > /tmp/r/$S-remove.log 2>&1 || { tail -5 /tmp/r/$S-remove.log; echo done-failed; exit 1; }
python3 -c "import json; r=json.load(open('/tmp/r/$S/removed/removal.json')); print(r['psnr_outside_hole'], r['psnr_revealed'], r['effects'])"
python3 .bench/s4/holevar.py /tmp/r/$S /tmp/r/$S-h 0 -1 -2 2>&1 | grep RESULT
python3 .bench/s4/dump.py /tmp/r/$S $OBJ $OUT/$S 2>&1 | tail -2
cp /tmp/r/$S/removed/removal.json $OUT/${S}_removal.json; cp /tmp/r/$S/metrics.json $OUT/${S}_metrics.json
echo "done $(( $(date +%s) - t0 )) s"
