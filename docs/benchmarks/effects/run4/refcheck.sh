# statue only: base run, stages, then Init and Ref with telea and exemplar side by side; scores copied as they land
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site || exit
python3 -c "from gsplat.cuda._backend import _C" || exit 1
R=/tmp/rc/run-statue; mkdir -p /tmp/rc $OUT/rc; cp -r .bench/statue /tmp/rc/
t() { local s=$(date +%s); "$@" > /tmp/rc/last.log 2>&1; echo "$(( $(date +%s) - s )) s rc=$?: $*"; grep -v '^{' /tmp/rc/last.log | tail -1; }
t python3 -m engine train --scene /tmp/rc/statue --out $R --max-gaussians 100000 --device cuda
cp $R/metrics.json $OUT/rc/
t python3 -m engine remove --run $R --object statue --device cuda
t python3 -m engine holes --run $R --device cuda
for ip in telea exemplar; do t python3 -m engine inpaint --run $R --inpainter $ip; done
cp $R/removed/removal.json $R/holes/holes.json $OUT/rc/ 2>/dev/null
for ip in telea exemplar; do for m in init reference; do
  ( python3 -m engine complete --run $R --method $m --inpainter $ip --steps 10000 --device cuda > /tmp/rc/$m-$ip.log 2>&1
    echo "$m $ip rc=$?"; grep -v '^{' /tmp/rc/$m-$ip.log | tail -1
    for c in $R/complete/*-$ip/; do b=$(basename "$c"); cp "$c/scores.json" "$OUT/rc/${b}_scores.json" 2>/dev/null; cp "$c/scene/reference_fill.json" "$OUT/rc/${b}_reference_fill.json" 2>/dev/null; done ) &
done; done
wait
