# The README's "Your own capture" on the GPU: SfM capture of the 48-view livingroom (no masks), 30k steps.
set -u
export CAPTURE=$PWD/.bench/cap-pinhole RUN=/tmp/e2e/run SPLATFILL_CACHE=/tmp/e2e/cache
mkdir -p /tmp/e2e
t() { local s=$(date +%s); "$@" > /tmp/e2e/last.log 2>&1; local rc=$?; echo "$(( $(date +%s) - s )) s rc=$rc: $*"; grep -v '^{"stage\|^{"event' /tmp/e2e/last.log | tail -2; }
t python3 -m engine info --scene $CAPTURE
t python3 -m engine train --scene $CAPTURE --out $RUN --max-gaussians 100000 --device cuda
t python3 -m engine segment --run $RUN --auto --device cuda
t python3 -m engine remove --run $RUN --object object_1 --device cuda
t python3 -m engine holes --run $RUN --device cuda
t python3 -m engine inpaint --run $RUN --inpainter telea
t python3 -m engine complete --run $RUN --method init --inpainter telea --device cuda
mkdir -p $OUT/e2e; cp $RUN/segments/sheet.png $OUT/e2e/segments.png; cp $RUN/segments/objects.json $RUN/metrics.json $OUT/e2e/
cp $RUN/holes/sheet.png $OUT/e2e/holes.png; python3 -c "import json,sys; d=json.load(open('$RUN/holes/holes.json')); d.pop('views'); print(json.dumps(d))" > $OUT/e2e/holes.json
cp $RUN/complete/*/scores.json $OUT/e2e/ 2>/dev/null; cp $RUN/removed/removal.json $OUT/e2e/ 2>/dev/null
