# On the device, once recv.sh has everything: the whole matrix of seed 0 as one benchmark run, its cells as Ray tasks
# on the machine's GPUs (base runs at the defaults: 30k steps, 300k budget; completions that train a new scene
# 10k steps, FT a tenth of the base run's; FT's perceptual term ST-LPIPS; FID, KID and ST-LPIPS columns filled from
# /tmp/weights). It outlives the call; collect.sh waits for it. METHODS (the benchmark's cells, default the five
# below) adds e.g. init-warm reference-warm direct-warm; give collect.sh the same METHODS.
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3) SPLATFILL_WEIGHTS=/tmp/weights
B=/tmp/b; [ -d $B/code ] || cp -r . $B/code
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1  # built once, before the tasks
cd $B/code || exit 1
# (not `cd X && setsid ... &`: the & would then fork a subshell that holds the caller's stdout until the benchmark
# ends, and a call piping start.sh into tail waited out its limit: 300 s of device time in run 2)
setsid nohup python3 scripts/benchmark.py --scenes $(ls -d $B/scenes/*/) --methods ${METHODS:-init reference ft3 ftall direct} \
  --inpainters telea exemplar --seeds ${SEED:-0} --out $B/out --complete-steps 10000 --device cuda > $B/runner.log 2>&1 < /dev/null &
sleep 20; tail -5 $B/runner.log; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv
