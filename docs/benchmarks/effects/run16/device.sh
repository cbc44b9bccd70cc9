# On the device (issue 16's overshoot, issue 17's warm cells), after recv.sh has livingroom_s0 and statue_s0 in
# /tmp/b/scenes: each scene's matrix of Init, Ref and Direct from scratch and [warm] (today's cell names; run 16 ran
# them as init, init-warm, ... at d355abe, before warm became the default), exemplar, seed 0, on a GPU of
# its own (CUDA_VISIBLE_DEVICES; the serial scheduler, so Ray need not be carried), each into its own --out. It
# outlives the call; `bash docs/benchmarks/effects/run16/collect.sh SECONDS` waits for it, then runs overshoot.py on
# each base run and packs the records.
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3)
B=/tmp/b; [ -d $B/code ] || cp -r . $B/code
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1  # built once, before both
cd $B/code || exit 1
# SCENES (default both) picks fewer where one GPU must do it all: one scene's run is about 800 s on an H100
gpus=$(nvidia-smi -L | wc -l); k=0; for s in ${SCENES:-livingroom_s0 statue_s0}; do
  CUDA_VISIBLE_DEVICES=$((k % gpus)) setsid nohup python3 scripts/benchmark.py --scenes $B/scenes/$s \
    --methods init-scratch init reference-scratch reference direct-scratch direct --inpainters exemplar --seeds 0 \
    --out $B/out16_$s --complete-steps 10000 --device cuda --scheduler serial > $B/r16_$s.log 2>&1 < /dev/null &
  k=$((k + 1)); done
sleep 20; tail -2 $B/r16_*.log; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv
