# On the device: collect.sh for each seed of SEEDS (default "0 1", when start.sh ran with SEED="0 1") into
# $OUT/seed<N>/, waiting up to $1 s for the benchmark first. With one scene that is four files a seed (logs,
# records, the scene's sheets, its MP4 when imageio-ffmpeg was carried), within a call's eight.
top=$OUT; wait=$1
for s in ${SEEDS:-0 1}; do
  mkdir -p $top/seed$s; OUT=$top/seed$s SEED=$s bash docs/benchmarks/full/collect.sh $wait; wait=0
done
