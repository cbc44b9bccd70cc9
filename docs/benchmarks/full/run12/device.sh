# Run 12 (issue 18's "10 min on one H100"), session 25: livingroom_s0 seed 0's whole matrix alone on a one-H100
# machine (`nvidia-h100-x1`, 16 cores), run 9's settings. Every earlier matrix ran on H200s, beside other chains.
# Calls back to back (R12 = bash docs/benchmarks/full/run12/device.sh; run 9's script under it):
#   1 carry .whl .bench/full_1     `R12 recv`
#   2 carry .bench/ray1            `R12 recv`
#   3 carry .bench/ray2            `R12 recv && R12 start`
#   4 carry .bench/fid1 .bench/fid2  `R12 recv`
#   5 carry .bench/fid3 .bench/fid4  `R12 recv; R12 finish 540`: waits for every chain's last cell, then collects in
#     the same command (about 30 s: the statue's `finish 575` ran past the 600 s a call may take, and its collect
#     needed a call of its own).
# Then on a fresh machine the same calls with CHAINS=0:statue_s0:0 and .bench/full_3 .bench/full_4 in call 1 for
# the statue (the slowest family on the H200s, 571-651 s there).
B=/tmp/b
export CHAINS=${CHAINS:-"0:livingroom_s0:0"}
case $1 in
finish)
  end=$(( $(date +%s) + $2 ))
  done_all() { for c in $CHAINS; do IFS=: read gpu sc s <<< "$c"; grep -q "10/10" $B/runner_${sc}_$s.log 2>/dev/null || return 1; done; }
  while [ $(date +%s) -lt $end ] && ! done_all; do sleep 10; done
  tail -n 2 $B/runner_*.log; done_all && bash docs/benchmarks/full/run9/device.sh collect;;
*) bash docs/benchmarks/full/run9/device.sh "$@";;
esac
