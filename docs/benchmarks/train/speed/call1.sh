# Issue 17 item 2, first device call: profile a livingroom_s0 training (640x480, 100 views, 300k budget)
# at step 7000 and time the variants (variants.py). Carry .bench/w (wheels), .bench/p1 (scene parts), .gsplat_build.
python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site .bench/w/*.whl
export PYTHONPATH=/tmp/site:.
bash docs/benchmarks/train/speed/gsplat_cached.sh
mkdir -p /tmp/parts /tmp/scenes && cp .bench/p1/* /tmp/parts/ && python3 docs/benchmarks/effects/run8/unpack.py /tmp/parts /tmp/scenes
/usr/bin/time -f "gsplat import %e s" python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()"
nvidia-smi --query-gpu=name,memory.used --format=csv
python3 docs/benchmarks/train/speed/variants.py /tmp/scenes/livingroom_s0 $OUT/variants.json > $OUT/variants.log 2>&1
tail -150 $OUT/variants.log
