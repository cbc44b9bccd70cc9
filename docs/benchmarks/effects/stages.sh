# On the GPU machine, call A: base runs (30k, 100k budget), removal with effects, holes and one inpainter for
# two scenes side by side:  bash stages.sh INPAINTER [direct]   (direct: also `inpaint --source input`)
inpainter=$1 direct=${2:-}
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site || exit
python3 -c "from gsplat.cuda._backend import _C" || exit 1
mkdir -p /tmp/r16; cp -r .bench/livingroom .bench/statue /tmp/r16/
t() { local s=$(date +%s); "$@" > /tmp/r16/last-$$.log 2>&1; local rc=$?; echo "$(( $(date +%s) - s )) s rc=$rc: $*"; grep -v '^{' /tmp/r16/last-$$.log | tail -2; }
for s in livingroom:plush statue:statue; do
  name=${s%%:*} obj=${s##*:}
  ( R=/tmp/r16/run-$name
    t python3 -m engine train --scene /tmp/r16/$name --out $R --max-gaussians 100000 --device cuda
    t python3 -m engine remove --run $R --object $obj --device cuda
    t python3 -m engine holes --run $R --device cuda
    t python3 -m engine inpaint --run $R --inpainter $inpainter
    [ -z "$direct" ] || t python3 -m engine inpaint --run $R --inpainter $inpainter --source input ) &
done
wait
