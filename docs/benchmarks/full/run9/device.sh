# Run 9 (issue 18, item 1; issue 16's spread over seeds), run in session 23 on a four-GPU host: livingroom_s0's
# whole matrix on one GPU and, beside it on the same host at the same time, the same matrix (same seed) under one
# Ray instance that sees two GPUs; on the fourth GPU, livingroom seed 1 (issue 16's second seed at today's code).
# Side by side, so the ratio is of one host and one load (run 8's 559 s came from another host). Chains are
# GPUs:scene:seed[:tag]; a tag keeps a chain's folder, start time and log apart from an untagged one of the same
# scene and seed (run 8's start reads it). Everything else is run 8's script (R8 = bash docs/benchmarks/full/run8/device.sh):
#   1 carry .whl .bench/full_1            `R9 recv`           (livingroom; gsplat builds behind)
#   2 carry .bench/ray1                   `R9 recv`
#   3 carry .bench/ray2                   `R9 recv && R9 start`
#   4 carry .bench/fid1 .bench/fid2       `R9 recv`
#   5 carry .bench/fid3 .bench/fid4       `R9 recv`
#   then `R9 wait N` until done, `R9 collect` (the untagged chains through run 8's collect; the tagged one's
#   records, log and start time beside them).
# The prediction from run 8's livingroom (training 172 s, removal 24.5, holes 28.2, then ten cells in two
# training slots a GPU): about 200 s of base stages on one GPU, then the cells over four slots instead of two,
# so about 200 + 360 / 2 = 380 s against 559: 1.5x, short of issue 18's 1.8x (the base stages stay serial).
# Measured (session 23, 4x H200): 452 s on two GPUs against 571 s on one beside it, 1.26x: Direct's exemplar
# inpainting (203 s beside the trainings) follows the base stages on the critical path (docs/BENCHMARKS.md, "Run 9").
B=/tmp/b; R8=docs/benchmarks/full/run8/device.sh
export CHAINS=${CHAINS:-"0:livingroom_s0:0 1,2:livingroom_s0:0:x2 3:livingroom_s0:1"}
untagged() { for c in $CHAINS; do [ $(tr -cd : <<< "$c" | wc -c) = 2 ] && echo -n "$c "; done; }
case $1 in
collect)
  CHAINS="$(untagged)" bash $R8 collect
  mkdir -p $B/tagged; for c in $CHAINS; do IFS=: read gpu sc s tag <<< "$c"; [ -n "$tag" ] || continue
    name=${sc}_${s}_$tag; cp $B/runner_$name.log $B/start_$name $B/tagged/
    cp $B/o_$name/results.json $B/tagged/${name}.results.json
    cp $B/o_$name/work/$sc/seed$s/stage_times.json $B/tagged/${name}.stage_times.json; done
  (cd $B && tar czf $OUT/tagged.tgz tagged); ls -la $OUT;;
*) bash $R8 "$@";;
esac
