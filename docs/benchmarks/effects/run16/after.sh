# On the device, once device.sh's cells are done (collect.sh says so): overshoot.py on each base run (livingroom on
# GPU 0, statue on GPU 1) and others_margin.sh (GPU 1) in the background, while the antialias pair
# (docs/benchmarks/train/antialias/device.sh) trains in the foreground, one mode per GPU; then collect.sh packs it all.
# The cells' own seconds are measured before any of this starts; the antialias pair's train_seconds are not clean
# (shared GPUs), only its PSNR and worst-view gap are the result.
B=/tmp/b; export PYTHONPATH=/tmp/site:$B/code; k=0
for s in ${SCENES:-livingroom_s0 statue_s0}; do d=$B/out16_$s/work/$s/seed0
  obj=$(python3 -c "import json,sys; print([o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')][0])" $B/scenes/$s/masks/objects.json)
  [ -f $d/run/removed/removal.json ] && [ ! -f $d/overshoot.txt ] && CUDA_VISIBLE_DEVICES=$k setsid nohup python3 \
    $B/code/docs/benchmarks/effects/run16/overshoot.py $d/run $obj --device cuda > $d/overshoot.txt 2>&1 < /dev/null &
  k=$((k + 1)); done
CUDA_VISIBLE_DEVICES=$(( $(nvidia-smi -L | wc -l) - 1 )) setsid nohup bash $B/code/docs/benchmarks/effects/run16/others_margin.sh \
  > /tmp/om.log 2>&1 < /dev/null &
(cd $B/code && bash docs/benchmarks/train/antialias/device.sh)
