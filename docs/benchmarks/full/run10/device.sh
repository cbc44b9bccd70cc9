# Run 10 (issues 16, 18), prepared in session 23, changed and run in session 24 on a four-GPU host:
# - GPU 0: statue_s0, training seed 1, one GPU; GPUs 1 and 2: the same scene and seed under one Ray that sees both
#   (tag x2), started in the same second: the statue's one-to-two-GPU ratio side by side (run 9 had livingroom's,
#   571 / 452 s), and issue 16's second statue seed at today's code.
# - GPU 3: the linear-light relight's judgement (../../effects/session23/judge.sh), in the background.
# - first, on that host before anything else runs: exemplar's search as a correlation (d1a4076) against the unrolled
#   matrix before it, on the GPU and on the CPU (../../inpaint/search_speed.py), to choose how its views go at once.
# Run 9's tabletop seed 0 rerun is left out: its removal, hole and completion code were already today's (run 8).
# Calls back to back (R10 = bash docs/benchmarks/full/run10/device.sh; run 9's script under it):
#   1 carry .whl .bench/full_1 .bench/oldex    `R10 recv && R10 search`   (livingroom for the search and the judge)
#   2 carry .bench/full_3 .bench/full_4        `R10 recv`                 (statue)
#   3 carry .bench/ray1                        `R10 recv`
#   4 carry .bench/ray2                        `R10 recv && R10 start`    (start copies this call's tree)
#   5 carry .bench/fid1 .bench/fid2            `R10 recv`
#   6 carry .bench/fid3 .bench/fid4            `R10 recv && R10 judge`
#   then `R10 finish N`: waits up to N s, then collects (the judge's and the search's outputs come back in base.tgz's
#   ex/). Session 24 waited in one call and collected in the next: the machine went back between the two (30 s
#   idle) and every record was lost, so the wait and the collect are one command now.
B=/tmp/b
export CHAINS=${CHAINS:-"0:statue_s0:1 1,2:statue_s0:1:x2"}
case $1 in
search)
  mkdir -p $B/ex; export PYTHONPATH=/tmp/site:.; S=$B/scenes/livingroom_s0
  CUDA_VISIBLE_DEVICES=3 python3 docs/benchmarks/inpaint/search_speed.py $S 16 1,8 --old=.bench/oldex/exemplar_old.py \
    2>&1 | tee $B/ex/search_gpu.txt
  CUDA_VISIBLE_DEVICES= python3 docs/benchmarks/inpaint/search_speed.py $S 16 1,16 2>&1 | tee $B/ex/search_cpu.txt;;
judge)
  rm -rf /tmp/jcode && cp -r . /tmp/jcode && cd /tmp/jcode && JOUT=$B/ex CUDA_VISIBLE_DEVICES=${JUDGE_GPU:-3} OMP_NUM_THREADS=16 \
    setsid nohup bash docs/benchmarks/effects/session23/judge.sh > $B/ex/judge.log 2>&1 < /dev/null & sleep 5;;
wait)
  end=$(( $(date +%s) + $2 ))
  while [ $(date +%s) -lt $end ] && ! { grep -q "10/10" $B/runner_statue_s0_1.log 2>/dev/null &&
    grep -q "10/10" $B/runner_statue_s0_1_x2.log 2>/dev/null && [ -f $B/ex/judge.txt ]; }; do sleep 10; done
  tail -n 1 $B/runner_*.log; tail -n 3 $B/ex/judge.log;;
finish)
  bash $0 wait $2; bash $0 collect;;
*) bash docs/benchmarks/full/run9/device.sh "$@";;
esac
