# Run 7 (issues 16, 17, 18), prepared in session 20, run in session 21 (README.md beside this file): the code (gsplat's tiles of 8 pixels, no
# torch._dynamo import, FID by singular values) on one four-GPU host, everything at once:
#   GPU 0: livingroom_s0 seed 0, Ray seeing this GPU alone, one training at a time (the default): issue 18's
#          matrix on one GPU against run 6's 932 s and run 5's serial 876 s.
#   GPU 1: the same with --trainings-per-gpu 2 (two cells training on the GPU at once; a step is bound by the
#          host, run 6).
#   GPU 2: `python -m engine train` at the defaults (30k steps), then a profile of its step: the tile's whole
#          training against run 6's 173.6 s (estimate about 160 s).
#   GPU 3: statue_s0 trained at the defaults, then every view rendered: its test renders come back for issue 17's
#          worst view (0065, 6 dB below the mean in run 4), whose error was never seen.
# Cells record where their time goes (`phases` in each record: load, scene, train, train_loop, score, process),
# and collect crops every test view's true hole from the one-GPU cells (hole_crops.py; issue 16's livingroom).
# Calls, as run 6 (each carries at most about 59 MiB beside the tree):
#   1 carry .whl .bench/ray1             `device.sh recv`
#   2 carry .bench/full_1 .bench/full_3 .bench/full_4   `device.sh recv && device.sh train`
#   3 carry .bench/ray2                  `device.sh recv && device.sh start`
#   4 carry .bench/fid1 .bench/fid2      `device.sh recv`
#   5 carry .bench/fid3 .bench/fid4      `device.sh recv && device.sh wait 480`
#   then `device.sh wait N`, `device.sh collect 0 0`
B=/tmp/b; mkdir -p $B
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3) SPLATFILL_WEIGHTS=/tmp/weights
METHODS="init reference ft3 ftall direct"; INPAINTERS="telea exemplar"; RUN4=docs/benchmarks/full/run4/device.sh
bench() {  # $1 the GPUs it sees, $2 out folder, then the scheduler's flags
  gpus=$1 out=$2; shift 2; date +%s > $B/start_$(basename $out)
  CUDA_VISIBLE_DEVICES=$gpus setsid nohup python3 scripts/benchmark.py --scenes $B/scenes/livingroom_s0 \
    --methods $METHODS --inpainters $INPAINTERS --seeds 0 --out $out --complete-steps 10000 --device cuda "$@" \
    > $B/runner_$(basename $out).log 2>&1 < /dev/null &
}
built() { for k in $(seq 60); do grep -q built $B/gsplat.log && break; sleep 5; done; cat $B/gsplat.log; }
case $1 in
recv)
  bash $RUN4 recv; python3 -c "import ray; print('ray', ray.__version__)" 2>&1 | tail -1;;
train)  # GPUs 2 and 3, started with setsid: a call's own process group ends with the call
  built; rm -rf $B/tcode $B/t; cp -r . $B/tcode; mkdir -p $B/t
  (cd $B/tcode && setsid nohup bash docs/benchmarks/full/run7/device.sh chain > $B/t/chain.log 2>&1 < /dev/null &)
  (cd $B/tcode && setsid nohup bash docs/benchmarks/full/run7/device.sh statue > $B/t/statue_chain.log 2>&1 < /dev/null &)
  sleep 20; ls $B/t;;
chain)
  export CUDA_VISIBLE_DEVICES=2 OMP_NUM_THREADS=16 MKL_NUM_THREADS=16; S=$B/scenes/livingroom_s0
  python3 -m engine train --scene $S --out $B/t/tile8 --device cuda > $B/t/tile8.log 2>&1
  cp $B/t/tile8/metrics.json $B/t/tile8.metrics.json
  python3 scripts/profile_train.py --scene $S --until 7000 --steps 500 --json $B/t/profile.json > $B/t/profile.log 2>&1
  echo done > $B/t/.done;;
statue)  # GPU 3: the statue at the defaults, every view rendered, the test views' renders packed
  export CUDA_VISIBLE_DEVICES=3 OMP_NUM_THREADS=16 MKL_NUM_THREADS=16; S=$B/scenes/statue_s0
  python3 -m engine train --scene $S --out $B/t/statue --device cuda > $B/t/statue.log 2>&1
  cp $B/t/statue/metrics.json $B/t/statue.metrics.json
  python3 -m engine cameras --scene $S --out $B/t/statue_cameras.json && python3 -m engine render \
    --ply $B/t/statue/point_cloud.ply --cameras $B/t/statue_cameras.json --out $B/t/statue_renders --device cuda
  (cd $B/t/statue_renders && tar czf $B/t/statue_test.tgz $(python3 -c \
    "import json,sys; print(*json.load(open(sys.argv[1]))['test'])" $S/split.json))
  echo done > $B/t/.statue_done;;
start)
  built; rm -rf $B/code; cp -r . $B/code; cd $B/code || exit 1
  bench 0 $B/o_one  # Ray, one GPU, one training at a time
  bench 1 $B/o_pair --trainings-per-gpu 2  # Ray, one GPU, two trainings at once
  sleep 40; tail -n 3 $B/runner_*.log; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv;;
wait)
  bash $RUN4 wait $2; for f in $B/start_*; do echo "$f $(cat $f)"; done; ls $B/t; tail -n 2 $B/t/*.log;;
collect)  # run 6's: the one-training matrix (o_one) through the run-3 collectors; every record of o_*, the training;
  # then the holes of the one-GPU cells cropped, and the statue's test renders
  bash docs/benchmarks/full/run6/device.sh collect $2 $3
  mkdir -p $B/crops; python3 docs/benchmarks/full/run7/hole_crops.py $B/scenes/livingroom_s0 $B/o_one/work/livingroom_s0/seed0/run \
    $B/crops > $B/crops/summary.txt 2>&1; cat $B/crops/summary.txt; (cd $B && tar czf $OUT/crops.tgz crops)
  cp $B/t/statue_test.tgz $OUT/ 2>/dev/null; ls -la $OUT;;
esac
