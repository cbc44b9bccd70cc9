# Run 8 (issues 16, 17, 18), prepared in session 21, run in session 22 on two GPUs (README.md): the code after run 7 (two trainings a GPU by
# default, the hole masks a Ray task of their own that the direct baseline's inpainting does not wait for, scenes
# with unseen/ so every training reports worst_view_gap_seen) on one four-GPU host, one scene's matrix per GPU,
# each under its own Ray instance seeing that GPU alone (so each is issue 18's one-GPU matrix):
#   GPU 0: livingroom_s0, training seed 0 (run 7: 595-603 s with two trainings a GPU, before the holes task)
#   GPU 1: statue_s0, seed 0 (its worst view over seen pixels from a whole benchmark's base run)
#   GPU 2: livingroom_s0, seed 1 (issue 16's spread over seeds at today's code)
#   GPU 3: tabletop_s0, seed 0, started when its last part arrives (call 6)
# collect: run 6's collectors for every chain, each base run's test renders (the green relit shadow: what the
# training made of the shadow against images/), every metrics.json (worst_view_gap_seen).
# Calls (each carries at most about 59 MiB beside the tree; the tabletop's first two parts need a call alone):
#   1 carry .whl .bench/ray1                             `device.sh recv`
#   2 carry .bench/full_1 .bench/full_3 .bench/full_4    `device.sh recv`
#   3 carry .bench/ray2                                  `device.sh recv && device.sh start`
#   4 carry .bench/fid1 .bench/fid2                      `device.sh recv`
#   5 carry .bench/fid3 .bench/fid4                      `device.sh recv`
#   6 carry .bench/full_2                                `device.sh recv && device.sh start`  (the tabletop)
#   then `device.sh wait N` until livingroom seed 0's matrix is done, `device.sh exemplar` (session 22: exemplar
#   on GPU 0 over that run's 100 direct regions, one view at a time against 4 and 8 processes, beside the other
#   matrices), `device.sh wait N` until all are done, `device.sh collect`
B=/tmp/b; mkdir -p $B
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3) SPLATFILL_WEIGHTS=/tmp/weights
METHODS="init reference ft3 ftall direct"; INPAINTERS="telea exemplar"; RUN4=docs/benchmarks/full/run4/device.sh
CHAINS=${CHAINS:-"0:livingroom_s0:0 1:statue_s0:0 2:livingroom_s0:1 3:tabletop_s0:0"}  # GPU:scene:seed (session 22 on two GPUs: livingroom seed 0 and the tabletop)
built() { for k in $(seq 60); do grep -q built $B/gsplat.log && break; sleep 5; done; cat $B/gsplat.log; }
case $1 in
recv)
  bash $RUN4 recv; python3 -c "import ray; print('ray', ray.__version__)" 2>&1 | tail -1;;
start)  # every chain whose scene has arrived and that has not started
  built; [ -d $B/code ] && [ -f $B/code/.copied ] || { rm -rf $B/code; cp -r . $B/code; touch $B/code/.copied; }
  cd $B/code || exit 1
  # GPUs:scene:seed[:tag] (run 9: a tag keeps a chain apart from an untagged one of the same scene and seed)
  for c in $CHAINS; do IFS=: read gpu sc s tag <<< "$c"; name=${sc}_$s${tag:+_$tag}
    [ -f $B/scenes/$sc/.ready ] && [ ! -f $B/start_$name ] || continue
    date +%s > $B/start_$name
    CUDA_VISIBLE_DEVICES=$gpu setsid nohup python3 scripts/benchmark.py --scenes $B/scenes/$sc --methods $METHODS \
      --inpainters $INPAINTERS --seeds $s --out $B/o_$name --complete-steps 10000 --device cuda \
      > $B/runner_$name.log 2>&1 < /dev/null &
  done
  sleep 30; tail -n 2 $B/runner_*.log; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv;;
wait)
  bash $RUN4 wait $2; for f in $B/start_*; do echo "$f $(cat $f)"; done; cat $B/ex/*.txt 2>/dev/null;;
exemplar)  # in the background; its table lands in $B/ex and comes back with collect
  mkdir -p $B/ex; cd $B/code && CUDA_VISIBLE_DEVICES=0 OUT=$B/ex RUN=$B/o_livingroom_s0_0/work/livingroom_s0/seed0/run \
    SOURCE=input WORKERS="1 4 8" PARALLEL=processes setsid nohup bash docs/benchmarks/inpaint/gpu_workers.sh \
    > $B/ex/log 2>&1 < /dev/null & sleep 5; cat $B/ex/log;;
collect)  # records and sheets through run 6's and run 3's collectors, one seed at a time; then what run 8 adds
  mkdir -p $B/out/work; for c in $CHAINS; do IFS=: read gpu sc s <<< "$c"; mkdir -p $B/out/work/$sc
    ln -sfn $B/o_${sc}_$s/work/$sc/seed$s $B/out/work/$sc/seed$s; done
  for f in $B/start_*; do echo "$f $(cat $f)"; done > $B/bench_starts.log; nvidia-smi -L >> $B/bench_starts.log
  seeds=$(for c in $CHAINS; do IFS=: read gpu sc s tag <<< "$c"; echo $s; done | sort -u)  # run 10: seed 1 alone
  first=$(head -1 <<< "$seeds")
  for s in $seeds; do SEED=$s PERCEPTUAL=st-lpips METHODS="$METHODS" INPAINTERS="$INPAINTERS" \
    bash docs/benchmarks/full/collect.sh 0 > $B/collect_$s.log 2>&1; mkdir -p $OUT/seed$s
    # at most 8 files come back: the first seed's sheets and logs, the others' records only
    [ $s = $first ] || rm -f $OUT/sheets_*.tgz $OUT/logs.tgz
    mv $OUT/*.tgz $OUT/seed$s/; done
  rm -rf $B/base && mkdir -p $B/base && for c in $CHAINS; do IFS=: read gpu sc s <<< "$c"; r=$B/o_${sc}_$s/work/$sc/seed$s/run
    [ -f $r/point_cloud.ply ] || continue; cp $r/metrics.json $B/base/${sc}_$s.metrics.json
    python3 -m engine cameras --scene $B/scenes/$sc --out $B/cams.json && python3 -m engine render --ply \
      $r/point_cloud.ply --cameras $B/cams.json --out $B/render_${sc}_$s --device cuda > /dev/null 2>&1
    (cd $B/render_${sc}_$s && tar czf $B/base/${sc}_$s.tgz $(python3 -c \
      "import json,sys; print(*json.load(open(sys.argv[1]))['test'])" $B/scenes/$sc/split.json)); done
  (cd $B && tar czf $OUT/base.tgz base runner_*.log ex) ; ls -la $OUT $OUT/*;;
esac
