# Issue 17 budget curve: bash .bench/budget.sh SCENE:BUDGET...  (0 = no budget), 30k steps each, side by side
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site || exit
python3 -c "from gsplat.cuda._backend import _C" || exit 1
mkdir -p /tmp/b17 $OUT/b17
for job in "$@"; do
  s=${job%%:*} b=${job##*:}
  ( s0=$(date +%s); python3 -m engine train --scene .bench/$s --out /tmp/b17/$s-$b --max-gaussians $b --device cuda > /tmp/b17/$s-$b.log 2>&1
    echo "$s $b rc=$? $(( $(date +%s) - s0 )) s"; grep -v '^{' /tmp/b17/$s-$b.log | tail -1
    cp /tmp/b17/$s-$b/metrics.json $OUT/b17/$s-$b.json ) &
done
wait
nvidia-smi --query-gpu=name,memory.used --format=csv
