# On the device: wait up to $1 s for start.sh's benchmark, then pack what has finished (run9/collect.sh does the
# packing; its own wait looks for a runner this chain does not have).
end=$(( $(date +%s) + $1 ))
while pgrep -f "[s]cripts/benchmark.py --scenes" > /dev/null && [ $(date +%s) -lt $end ]; do sleep 10; done
tail -3 /tmp/b/runner.log
SPLATFILL_WEIGHTS=/tmp/weights RUNNER=full-table-has-no-runner bash docs/benchmarks/effects/run9/collect.sh 0
# one before | after MP4 per scene (issue 18, item 4): the base run against Ref-exemplar's completed scene (Init's where
# Ref has none), 48 frames around the removed object, written by `python -m engine turntable`
export PYTHONPATH=/tmp/site:.; mkdir -p $OUT/mp4
python3 -c 'import imageio_ffmpeg' 2>/dev/null || { echo 'no imageio-ffmpeg (carry .bench/ff): no MP4'; exit 0; }
for d in /tmp/b/out/work/*/seed${SEED:-0}/run; do n=$(basename $(dirname $(dirname $d))); [ -f $OUT/mp4/$n.mp4 ] && continue
  after=""; for p in $d/complete/Ref-exemplar*/run/point_cloud.ply $d/complete/Init-exemplar*/run/point_cloud.ply; do
    [ -z "$after" ] && [ -f "$p" ] && after=$p; done  # (ls sorts its arguments: Init came first; a glob, since run 4's
    # cells end in [warm]: that run's collect found no Ref-exemplar folder and wrote no MP4)
  [ -n "$after" ] && python3 -m engine turntable --run $d --after $after --out /tmp/tt_$n --device cuda 2>&1 | tail -1 &&
    cp /tmp/tt_$n/turntable.mp4 $OUT/mp4/$n.mp4; done; ls -la $OUT/mp4
