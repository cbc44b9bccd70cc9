# session 5: train SCENE at the defaults, remove (object OBJ), hole masks, dump for CPU design of the contact relight
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null; export PYTHONPATH=/tmp/site:.
export PYTHONUNBUFFERED=1
S=$1; OBJ=$2; R=/tmp/r; mkdir -p $R
cp -r .bench/$S $R/scene_$S
t0=$(date +%s)
python3 -m engine train --scene $R/scene_$S --out $R/$S --device cuda > $R/$S-train.log 2>&1 || { tail -5 $R/$S-train.log; exit 1; }
echo "trained $S in $(( $(date +%s) - t0 )) s"; cp $R/$S/metrics.json $OUT/${S}_metrics.json
python3 -m engine remove --run $R/$S --object $OBJ --device cuda > $R/$S-remove.log 2>&1 || { tail -5 $R/$S-remove.log; exit 1; }
python3 -m engine holes --run $R/$S --device cuda > $R/$S-holes.log 2>&1 || { tail -5 $R/$S-holes.log; exit 1; }
python3 .bench/s5/dump5.py $R/$S $OUT/$S
echo "done $(( $(date +%s) - t0 )) s"
