# Run 6 (issue 18, item 1; issue 16's table at one code): one scene's matrix through the benchmark's default
# scheduler, Ray, on one GPU against two GPUs, both at once on one four-GPU host (livingroom_s0, training seed 0,
# the same settings as runs 4 and 5); the fourth GPU runs the statue's seed 0 serially at today's code (run 4's
# statue predates the other objects' shadows left dark). Written in session 19, not yet run.
# Why at once: one after the other, the two Ray matrices (about 750 and 500 s) and their set-up would take
# nearly all of a session's 1,800 s of device time. Each benchmark process starts a Ray instance of its own
# (`ray.init()` without an address starts a new local one; only `ray start` leaves one for others to join), and
# Ray sees only the GPUs CUDA_VISIBLE_DEVICES gives it. If the second instance fails to start, run `one` and
# `two` one after the other instead.
# The prediction to check (run 5's livingroom seed 0, serial: base stages 233 s, inpainting 167 s of which
# Direct's exemplar 129 s, ten cells 476 s): one GPU about 750 s (Direct's exemplar runs beside the cells), two
# about 490 s (the base stages stay serial), a ratio of about 1.5, short of the 1.8.
# Calls (the tree travels without docs' pictures, a sparse checkout: each call carries about 59 MiB beside it):
#   1 carry .whl .bench/ray1                      `device.sh recv`   (gsplat builds behind; Ray waits for part 2)
#   2 carry .bench/ray2 .bench/full_3             `device.sh recv`   (Ray installs)
#   3 carry .bench/full_1 .bench/full_4           `device.sh recv && device.sh start`
#   4 carry .bench/fid1 .bench/fid2               `device.sh recv`
#   5 carry .bench/fid3 .bench/fid4               `device.sh recv && device.sh wait 480`
#   then `device.sh wait N`, `device.sh collect 0 0` (the one-GPU matrix and the statue; the two-GPU one's
#   records go in raw.tgz: its cells are the one-GPU cells again, its wall time is what it measures)
B=/tmp/b; mkdir -p $B
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3) SPLATFILL_WEIGHTS=/tmp/weights
METHODS="init reference ft3 ftall direct"; INPAINTERS="telea exemplar"; RUN4=docs/benchmarks/full/run4/device.sh
bench() {  # $1 the GPUs it sees, $2 out folder, $3 scene, then the scheduler's flags
  gpus=$1 out=$2 sc=$3; shift 3; date +%s > $B/start_$(basename $out)
  CUDA_VISIBLE_DEVICES=$gpus setsid nohup python3 scripts/benchmark.py --scenes $B/scenes/$sc --methods $METHODS --inpainters $INPAINTERS \
    --seeds 0 --out $out --complete-steps 10000 --device cuda "$@" > $B/runner_$(basename $out).log 2>&1 < /dev/null &
}
case $1 in
recv)  # run 4's (wheels, scenes, weights, Ray; gsplat built behind from a copy of the first call's tree)
  bash $RUN4 recv; python3 -c "import ray; print('ray', ray.__version__)" 2>&1 | tail -1;;
start)
  for k in $(seq 60); do grep -q built $B/gsplat.log && break; sleep 5; done; cat $B/gsplat.log
  rm -rf $B/code; cp -r . $B/code; cd $B/code || exit 1  # the code as of this call, once the build from it is done
  bench 0 $B/o_one livingroom_s0  # Ray, one GPU
  bench 1,2 $B/o_two livingroom_s0  # Ray, two GPUs
  OMP_NUM_THREADS=16 MKL_NUM_THREADS=16 bench 3 $B/o_statue statue_s0 --scheduler serial  # (Ray sets its own)
  sleep 40; tail -n 3 $B/runner_*.log; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv;;
wait)
  bash $RUN4 wait $2; for f in $B/start_*; do echo "$f $(cat $f)"; done;;
collect)  # the one-GPU livingroom and the statue through the run-3 collectors; every JSON record of all three
  mkdir -p $B/out/work/livingroom_s0 $B/out/work/statue_s0
  ln -sfn $B/o_one/work/livingroom_s0/seed0 $B/out/work/livingroom_s0/seed0
  ln -sfn $B/o_statue/work/statue_s0/seed0 $B/out/work/statue_s0/seed0
  for f in $B/start_*; do echo "$f $(cat $f)"; done > $B/bench_starts.log; nvidia-smi -L >> $B/bench_starts.log
  SEED=0 PERCEPTUAL=st-lpips METHODS="$METHODS" INPAINTERS="$INPAINTERS" bash docs/benchmarks/full/collect.sh $3
  (cd $B && tar czf $OUT/raw.tgz $(find o_* -name "*.json" | grep -v -E "/images/|/scene/|point_cloud") runner_*.log);;
esac
