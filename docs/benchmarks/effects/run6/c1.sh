# session 4, machine 3: relaxed visual hull, removal and holes per share
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null; export PYTHONPATH=/tmp/site:.
export PYTHONUNBUFFERED=1
S=$1; OBJ=$2; OUT=/tmp/r/out; mkdir -p $OUT
mkdir -p /tmp/r; cp -r .bench/$S /tmp/r/scene_$S
t0=$(date +%s)
[ -f /tmp/r/$S/point_cloud.ply ] || python3 -m engine train --scene /tmp/r/scene_$S --out /tmp/r/$S --device cuda > /tmp/r/$S-train.log 2>&1 || { tail -5 /tmp/r/$S-train.log; echo done-failed; exit 1; }
echo "trained $S in $(( $(date +%s) - t0 )) s"
python3 .bench/s4/sharevar.py /tmp/r/$S $OBJ $OUT/$S 2>&1 | grep -E "SHARE|Error|error"; cp /tmp/r/$S/metrics.json $OUT/${S}_metrics.json
echo "done $(( $(date +%s) - t0 )) s"
