# Run 12 (issue 18's "10 min on one H100"), session 25: livingroom_s0 seed 0's whole matrix alone on a one-H100
# machine (`nvidia-h100-x1`, 16 cores), run 9's settings. Every earlier matrix ran on H200s, beside other chains.
# Calls back to back (R12 = bash docs/benchmarks/full/run12/device.sh; run 9's script under it):
#   1 carry .whl .bench/full_1     `R12 recv`
#   2 carry .bench/ray1            `R12 recv`
#   3 carry .bench/ray2            `R12 recv && R12 start`
#   4 carry .bench/fid1 .bench/fid2  `R12 recv`
#   5 carry .bench/fid3 .bench/fid4  `R12 recv`
#   6 `R12 finish 560`, then `R12 finish N` again if it has not ended: waits, then collects in the same command.
B=/tmp/b
export CHAINS=${CHAINS:-"0:livingroom_s0:0"}
case $1 in
finish)
  end=$(( $(date +%s) + $2 ))
  while [ $(date +%s) -lt $end ] && ! grep -q "10/10" $B/runner_livingroom_s0_0.log 2>/dev/null; do sleep 10; done
  tail -n 2 $B/runner_*.log; grep -q "10/10" $B/runner_livingroom_s0_0.log && bash docs/benchmarks/full/run9/device.sh collect;;
*) bash docs/benchmarks/full/run9/device.sh "$@";;
esac
