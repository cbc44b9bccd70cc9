# On the device, after recv.sh has the scene (default statue_s0): a base run at the defaults in the classic and in the
# antialiased rasterize mode at once, one per GPU (one after the other where there is one GPU), in the foreground
# (about 200 s on two H100s); $OUT/antialias.txt holds each run's test PSNR, worst-view gap and per-view PSNR.
export PYTHONPATH=/tmp/site:.; S=${SCENE:-/tmp/b/scenes/statue_s0}; gpus=$(nvidia-smi -L | wc -l)
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1  # built once, before both
k=0; for m in classic antialiased; do rm -rf /tmp/aa_$m
  CUDA_VISIBLE_DEVICES=$((k % gpus)) python3 docs/benchmarks/train/antialias/train_aa.py $S /tmp/aa_$m $m > /tmp/aa_$m.log 2>&1 &
  [ $gpus -lt 2 ] && wait; k=$((k + 1)); done; wait
tail -qn1 /tmp/aa_classic.log /tmp/aa_antialiased.log | tee $OUT/antialias.txt; nvidia-smi -L | head -1
