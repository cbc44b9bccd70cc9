# Run 10 (issue 16's and 18's last seed at today's code; issue 18's two-GPU matrix on the slowest family), prepared
# in session 23, not yet run. Run 9 left the statue with one seed at today's code (seed 0: 651 s on one GPU, over
# 10 minutes: its removed scene's exemplar took 126 s against livingroom's 58). This runs statue_s0's seed 1 on one
# GPU and, beside it on the same host from the same second, the same matrix under one Ray that sees two GPUs (so
# the statue's one-to-two-GPU ratio is side by side, as run 9's livingroom 571 / 452 s was). On a four-GPU host
# the fourth GPU runs tabletop_s0 seed 0 again at today's code (run 8's seed 0 ran at fc49615). Through run 9's
# script (R9 = bash docs/benchmarks/full/run9/device.sh), calls back to back:
#   1 carry .whl .bench/full_3 .bench/full_4   `R9 recv`          (statue; gsplat builds behind)
#   2 carry .bench/ray1                        `R9 recv`
#   3 carry .bench/ray2                        `CHAINS=... R9 recv && CHAINS=... R9 start`   (CHAINS below)
#   4 carry .bench/fid1 .bench/fid2            `R9 recv`
#   5 carry .bench/fid3 .bench/fid4            `R9 recv`
#   6 carry .bench/full_2                      `R9 recv && CHAINS=... R9 start`   (the tabletop, four GPUs only)
#   then waits (`grep -q 10/10 /tmp/b/runner_<chain>.log` in a loop) and `CHAINS=... R9 collect`.
# On a two-GPU host, CHAINS="0:statue_s0:1" alone (the ratio then needs a four-GPU host).
# Run 9 used 1,336 s of device time for two passes; this is one pass, about 900 s.
export CHAINS=${CHAINS:-"0:statue_s0:1 1,2:statue_s0:1:x2 3:tabletop_s0:0"}
exec bash docs/benchmarks/full/run9/device.sh "$@"
