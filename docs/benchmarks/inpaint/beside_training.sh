# On a one-GPU device call carrying .whl, .bench/full_1 (livingroom_s0) and .bench/exv16 (16 of its views):
# installs and builds as run 4's recv does, starts two trainings of livingroom_s0 at the defaults on the GPU (the
# matrix's two trainings a GPU), then, once both are in their loops, beside_training.py over the 16 views with 8
# processes; then the same alone once the trainings are stopped. Output: $OUT/beside_training.txt.
# Session 22 started it once on an H100 with 260 s of device time left: the install, gsplat's build and the
# trainings' start took most of it, and the first pass (one view at a time beside the trainings) had not
# finished its 16 views when the time ran out. Nothing measured yet.
B=/tmp/b; export PYTHONPATH=/tmp/site:.
bash docs/benchmarks/full/run4/device.sh recv > /dev/null 2>&1
for k in $(seq 60); do grep -q built $B/gsplat.log && break; sleep 5; done
for i in 1 2; do setsid nohup python3 -m engine train --scene $B/scenes/livingroom_s0 --out $B/t$i --device cuda \
  > $B/t$i.log 2>&1 < /dev/null & done
sleep 45; nvidia-smi --query-gpu=utilization.gpu,memory.used --format=csv,noheader
{ echo "# beside two trainings"; python3 docs/benchmarks/inpaint/beside_training.py .bench/exv16/livingroom_s0 16 8
  tail -c 300 $B/t1.log | tr '\r' '\n' | tail -1; pkill -f "engine train"; sleep 3
  echo "# alone"; python3 docs/benchmarks/inpaint/beside_training.py .bench/exv16/livingroom_s0 16 8; } 2>&1 \
  | tee $OUT/beside_training.txt
