# Issue 17's budget curve at 640x480/100 views, on the device after run9/recv.sh has unpacked the scenes (call it
# with RUNNER=none): every scene in $SCENES trained at every budget in $BUDGETS (0 = no budget, DefaultStrategy),
# 30k steps, then removal, holes and Init-exemplar at 10k steps, spread over the GPUs by run10's runner. Each
# (scene, budget) is a link <scene>_b<N> to the unpacked scene, which run9/jobs.sh trains with --max-gaussians N.
#   SCENES="livingroom_s0 statue_s0" BUDGETS="50000 100000 1000000 0" bash docs/benchmarks/budget/curve.sh
# then: METHODS=init RUNNER=run10 bash docs/benchmarks/effects/run9/collect.sh SECONDS
B=/tmp/b; names=""
for s in $SCENES; do for b in $BUDGETS; do
  [ -e $B/scenes/${s}_b$b ] || ln -s $B/scenes/$s $B/scenes/${s}_b$b; names="$names ${s}_b$b"; done; done
[ -d $B/code ] || cp -r . $B/code
pgrep -f "run10/[r]unner.sh" > /dev/null || (cd $B/code && METHODS=init COMPLETE="$names" INPAINTERS=exemplar \
  setsid nohup bash docs/benchmarks/effects/run10/runner.sh $names > $B/runner.log 2>&1 < /dev/null &)
sleep 2; echo "started:$names"; ls $B/scenes
#
# Staged for the next session (git-ignored; parts as in effects/run12/README.md): call 1 carries .whl,
# .gsplat_build and .bench/g1 (statue_s0 2of2, livingroom_s0 2of2), call 2 .bench/g2 (livingroom_s0 1of2,
# statue_s0 1of2), each `mkdir -p .bench/c && cp .bench/gN/* .bench/c/ && RUNNER=none bash
# docs/benchmarks/effects/run9/recv.sh`; then `SCENES="livingroom_s0 statue_s0" BUDGETS="50000 100000 1000000 0"
# bash docs/benchmarks/budget/curve.sh`; then collect.sh. The 300k points are the thirteenth trainings' (same
# scenes, same code path). About 15 min of device time on four GPUs.
