# issue 16, tabletop alone: telea cells start with the base run; exemplar cells start beside them once the holes exist
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null; export PYTHONPATH=/tmp/site
python3 -c "from gsplat.cuda._backend import _C" || exit 1
export SPLATFILL_ENGINE_PYTHON=$(command -v python3) PYTHONUNBUFFERED=1
mkdir -p /tmp/b/scenes; cp -r .bench/tabletop /tmp/b/scenes/
b() { setsid nohup python3 scripts/benchmark.py --scenes /tmp/b/scenes/tabletop --methods init reference --inpainters $1 \
    --seeds 0 --out /tmp/b/out --complete-steps 10000 --perceptual l1 --device cuda > /tmp/b/tabletop-$1.log 2>&1 < /dev/null & }
b telea; echo "started telea $(date)"
end=$(( $(date +%s) + 420 ))
while [ ! -d /tmp/b/out/work/tabletop/seed0/run/holes ] && [ $(date +%s) -lt $end ]; do sleep 5; done
[ -d /tmp/b/out/work/tabletop/seed0/run/holes ] && { b exemplar; echo "started exemplar $(date)"; }
cat /tmp/b/out/work/tabletop/seed0/stage_times.json 2>/dev/null; ls /tmp/b/out/work/tabletop/seed0/run/checkpoints 2>/dev/null
