# issue 16: Init vs Ref (telea, exemplar, 10k steps) at the default base run, one detached benchmark per scene
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>/dev/null; export PYTHONPATH=/tmp/site
python3 -c "from gsplat.cuda._backend import _C" || exit 1
export SPLATFILL_ENGINE_PYTHON=$(command -v python3) PYTHONUNBUFFERED=1
mkdir -p /tmp/b/scenes
for s in "$@"; do
  cp -r .bench/$s /tmp/b/scenes/
  setsid nohup python3 scripts/benchmark.py --scenes /tmp/b/scenes/$s --methods init reference --inpainters telea exemplar \
    --seeds 0 --out /tmp/b/out --complete-steps 10000 --perceptual l1 --device cuda > /tmp/b/$s.log 2>&1 < /dev/null &
  echo "started $s"
done
sleep 5; nvidia-smi --query-gpu=name,memory.used --format=csv
