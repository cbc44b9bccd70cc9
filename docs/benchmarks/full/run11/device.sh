# Run 11 (issues 16, 18), prepared in session 24, run in session 25 (records: README.md): run 10 again, with the statue's seed 0 beside it, since
# run 10's records were lost (../run10/README.md). On a four-GPU host, started in the same second:
# - GPU 0: statue_s0, training seed 0, one GPU (run 9's 651 s was with exemplar's old search on the GPU);
# - GPU 1: statue_s0, seed 1, one GPU (run 10: 515 s, the only number it kept);
# - GPUs 2 and 3: seed 1 under one Ray that sees both (tag x2): the statue's one-to-two-GPU ratio, side by side;
# - then, once the two-GPU chain is done, the linear relight's judgement on GPU 2 (../../effects/session23).
# Both statue seeds at one code give issue 16's statue targets over two seeds, and issue 18's 10 minutes.
# Calls strictly back to back (the machine goes back after 30 s idle; R11 = bash docs/benchmarks/full/run11/device.sh):
#   1 carry .whl .bench/full_3 .bench/full_4   `R11 recv`   (statue; gsplat builds behind)
#   2 carry .bench/ray1                        `R11 recv`
#   3 carry .bench/ray2                        `R11 recv && R11 start`
#   4 carry .bench/fid1 .bench/fid2            `R11 recv`
#   5 carry .bench/fid3 .bench/fid4            `R11 recv`
#   6 carry .bench/full_1                      `R11 recv && R11 phase1 540`   (livingroom, for the judgement)
#   7                                          `R11 finish 520`               (waits, then collects: one command)
# About 1,100 s of device time if the machine starts in 200 s.
B=/tmp/b; R10=docs/benchmarks/full/run10/device.sh
export CHAINS=${CHAINS:-"0:statue_s0:0 1:statue_s0:1 2,3:statue_s0:1:x2"}
all_done() {
  for c in $CHAINS; do IFS=: read gpu sc s tag <<< "$c"
    grep -q "10/10" $B/runner_${sc}_$s${tag:+_$tag}.log 2>/dev/null || return 1; done
  [ -f $B/ex/judge.txt ]; }
case $1 in
phase1)  # wait up to $2 s; the judgement starts on GPU 2 as soon as the two-GPU chain is done
  mkdir -p $B/ex; end=$(( $(date +%s) + $2 ))
  while [ $(date +%s) -lt $end ] && ! all_done; do
    [ -f $B/ex/judge.log ] || ! grep -q "10/10" $B/runner_statue_s0_1_x2.log 2>/dev/null || JUDGE_GPU=2 bash $R10 judge
    sleep 10; done
  tail -n 1 $B/runner_*.log; tail -n 3 $B/ex/judge.log 2>/dev/null;;
finish)
  bash $0 phase1 $2; bash $R10 collect;;
*) bash $R10 "$@";;
esac
