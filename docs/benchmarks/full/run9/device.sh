# Run 9 (issue 18, item 1; issue 16's spread over seeds), prepared in session 22, not yet run: for a two-GPU host
# (the only multi-GPU kind lent in session 22). Run 8 measured one scene's matrix on one H200 (livingroom_s0,
# seed 0: 559 s); this measures the same matrix over both GPUs of one host under one Ray instance (issue 18: at
# least 1.8x shorter than on one, at most 6 min), then, on the same warm host, livingroom seed 1 and the statue,
# one matrix a GPU (the spread over seeds at today's code; the statue's matrix at today's code).
# Everything goes through run 8's script with its chains given (GPUs:scene:seed; "0,1" lets one Ray see both):
#   1 carry .whl .bench/full_1                  `R8 recv`                       (gsplat builds behind)
#   2 carry .bench/ray1 .bench/full_3           `R8 recv`
#   3 carry .bench/ray2                         `R8 recv && CHAINS="0,1:livingroom_s0:0" R8 start`
#   4 carry .bench/fid1 .bench/full_4           `R8 recv`                       (the statue's second part)
#   5 carry .bench/fid2 .bench/fid3             `R8 recv`
#   6 carry .bench/fid4                         `R8 recv`
#   then `R8 wait N` until done; `CHAINS="0,1:livingroom_s0:0" R8 collect` (its wall time and records: a call);
#   then `CHAINS="0:livingroom_s0:1 1:statue_s0:0" R8 start`, `R8 wait N`, and collect with those chains.
# (R8 = bash docs/benchmarks/full/run8/device.sh.) The tree is 8.5 MiB: no call may carry more than about 55 MiB.
# The prediction (run 8's livingroom stages: training 172 s, removal 24.5, holes 28.2, Direct's exemplar 217 s
# beside the cells; ten cells of 28-68 s each, two trainings a GPU): about 200 s of base stages on one GPU, then
# the cells over four training slots instead of two, so about 200 + 360 / 2 = 380 s: 1.5x, short of 1.8x, and
# just over 6 min. Where the base stages bound it is what the target needs the user's decision on.
exec bash docs/benchmarks/full/run8/device.sh "$@"
