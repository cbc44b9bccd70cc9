# Run 4 of the full table (issues 16, 17, 18): livingroom_s0 and statue_s0 at today's code, the benchmark's
# training seeds 0 and 1, on four GPUs: each (scene, seed) is one serial benchmark process pinned to its own GPU,
# so each process's wall time is also one scene's whole matrix on one GPU (issue 18's 10-minute target).
# Why serial and not Ray: four equal chains on four GPUs leave Ray nothing to balance, and Ray's 80 MB wheel
# would take two more calls before the start (device time); the processes write apart (--out per chain) and
# one --report-only run over links joins them into one table.
#   call 1 carry .whl .bench/full_a           `bash docs/benchmarks/full/run4/device.sh recv`  (gsplat builds behind)
#   call 2 carry .bench/full_b .bench/full_c  `... recv && ... start`
#   calls 3-5 carry .bench/fid1, fid2, fid3   `... recv`  (FID Inception and ST-LPIPS into /tmp/weights)
#   call 6 carry .bench/ff                    `... recv && ... wait 540`
#   then `... collect 0 WAIT`, `... collect 1 0` (seed 0 brings the MP4s)
# Run 5 ran its chains through this script (../run5/device.sh, livingroom and tabletop); run 6 uses its recv and wait.
B=/tmp/b; mkdir -p $B
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3) SPLATFILL_WEIGHTS=/tmp/weights
CHAINS=${CHAINS:-"livingroom_s0:0 livingroom_s0:1 statue_s0:0 statue_s0:1"}  # (scene:seed) one per GPU; run 4 ran these
METHODS="init reference ft3 ftall direct"; INPAINTERS="telea exemplar"
case $1 in
recv)
  bash docs/benchmarks/full/recv.sh
  [ -d $B/code ] || { cp -r . $B/code; (cd $B/code && setsid nohup python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g(); print('built')" > $B/gsplat.log 2>&1 < /dev/null &); }
  cat $B/gsplat.log;;
start)
  for k in $(seq 60); do grep -q built $B/gsplat.log && break; sleep 5; done; cat $B/gsplat.log
  n=$(nvidia-smi -L | wc -l); i=0; cd $B/code || exit 1
  # each chain's share of the host's cores: four processes whose torch each took all 64 ran their first warm
  # cell at 1,500% CPU and 0% GPU for 6 minutes (threads spinning on each other) before this was set; Ray's
  # workers get it set by Ray, the serial processes did not
  export OMP_NUM_THREADS=$(( $(nproc) / n )) MKL_NUM_THREADS=$(( $(nproc) / n ))
  for c in $CHAINS; do sc=${c%:*}; s=${c#*:}
    [ -f $B/scenes/$sc/.ready ] || { echo "no $sc"; continue; }
    date +%s > $B/start_${sc}_$s
    CUDA_VISIBLE_DEVICES=$((i % n)) setsid nohup python3 scripts/benchmark.py --scenes $B/scenes/$sc --methods $METHODS \
      --inpainters $INPAINTERS --seeds $s --out $B/o_${sc}_$s --complete-steps 10000 --scheduler serial \
      --device cuda > $B/runner_${sc}_$s.log 2>&1 < /dev/null &
    i=$((i + 1)); done
  sleep 15; tail -n 2 $B/runner_*.log; nvidia-smi --query-gpu=index,name,utilization.gpu,memory.used --format=csv;;
wait)
  end=$(( $(date +%s) + $2 ))
  while pgrep -f "[s]cripts/benchmark.py --scenes" > /dev/null && [ $(date +%s) -lt $end ]; do sleep 10; done
  tail -n 1 $B/runner_*.log;;
collect)  # one seed's records, sheets, logs (and MP4s) into $OUT, through the run-3 collectors
  mkdir -p $B/out/work; for c in $CHAINS; do sc=${c%:*}; s=${c#*:}; mkdir -p $B/out/work/$sc
    [ -e $B/out/work/$sc/seed$s ] || ln -s $B/o_${sc}_$s/work/$sc/seed$s $B/out/work/$sc/seed$s; done
  for f in $B/start_*; do echo "$f $(cat $f)"; done > $B/bench_starts.log; nvidia-smi -L >> $B/bench_starts.log
  SEED=$2 PERCEPTUAL=st-lpips METHODS="$METHODS" INPAINTERS="$INPAINTERS" bash docs/benchmarks/full/collect.sh $3
  [ "$2" = 0 ] || rm -rf $OUT/mp4;;
esac
