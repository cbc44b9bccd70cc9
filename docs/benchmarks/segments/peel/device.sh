# NOT RUN YET. Session 27 began with 287 s of device time left (status was not read first): call 1 ran (gsplat
# built in 103 s, the three trainings started at 7.4 s per 1,000 steps) and the machine went back with 113 s left,
# too little for the ~220 s of training and the bench. A later session runs both calls as written.
#
# Session 27: `segment --auto` with wide pieces peeled (split_pieces, fa6729a) against the code before
# (before.patch undoes it on the current tree: `git diff HEAD fa6729a~1 -- engine/train/proposals.py`, made again
# whenever proposals.py changes), on the segments table's protocol: the three generated scenes at 320x240 with 48
# views (make_scene.py --views 48 --res 320 --samples 16 --seed 0 --gt test; carried without depth/, which
# neither training nor scoring reads), each trained 30k steps at a 100k budget, side by side on one GPU.
#   call 1, carry .whl .bench/segc:  bash docs/benchmarks/segments/peel/device.sh start
#   call 2 (straight after):         bash docs/benchmarks/segments/peel/device.sh bench
# start installs the wheels, builds gsplat and starts the three trainings detached; bench waits for them and
# runs scripts/bench_segments.py on each run with both codes: records and pictures in $OUT/peel.tgz (today/,
# before/, the runs' metrics.json), as a call brings back at most 8 files.
B=/tmp/seg; mkdir -p $B
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1
case $1 in
start)
  [ -d /tmp/site/gsplat ] || python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site .whl/*.whl
  cp -r .bench/segc $B/scenes
  python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g(); print('built')" || exit 1
  for s in livingroom statue tabletop; do
    setsid nohup python3 -m engine train --scene $B/scenes/$s --out $B/runs/$s --max-gaussians 100000 \
      --device cuda > $B/train-$s.log 2>&1 < /dev/null &
  done
  sleep 20; tail -n 1 $B/train-*.log;;
bench)
  while pgrep -f "[e]ngine train --scene" > /dev/null; do sleep 5; done
  tail -qn 1 $B/train-*.log; grep -h '"psnr"\|train_seconds' $B/runs/*/metrics.json
  rm -rf $B/before && cp -r . $B/before && patch -s -p1 -d $B/before < docs/benchmarks/segments/peel/before.patch || exit 1
  for s in livingroom statue tabletop; do
    python3 scripts/bench_segments.py --run $B/runs/$s --results $B/out/today 2>&1 | tail -n 1
    (cd $B/before && python3 scripts/bench_segments.py --run $B/runs/$s --results $B/out/before 2>&1 | tail -n 1)
  done
  for s in livingroom statue tabletop; do cp $B/runs/$s/metrics.json $B/out/$s-metrics.json; done
  python3 docs/benchmarks/segments/peel/summary.py $B/out/before $B/out/today
  tar czf $OUT/peel.tgz -C $B/out .;;
esac
