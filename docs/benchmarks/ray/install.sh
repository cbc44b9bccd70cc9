# On the device: put Ray 2.60.0 (Python 3.12) into /tmp/site beside the other wheels, in two calls, since its wheel
# (76 MB) is over what one call carries. Staged here, git-ignored: .bench/ray1 (ray.whl.part00) and .bench/ray2
# (ray.whl.part01, its dependencies' wheels, ray.sha256); made with `split -b 40M -d` of the wheel.
#   call 1 (carry .bench/ray1):  bash docs/benchmarks/ray/install.sh
#   call 2 (carry .bench/ray2):  bash docs/benchmarks/ray/install.sh
# Then `python3 scripts/benchmark.py ...` (PYTHONPATH=/tmp/site:.) runs its cells as Ray tasks on every GPU.
W=/tmp/raywheel; mkdir -p $W
cp .bench/ray1/* $W/ 2>/dev/null; cp .bench/ray2/* $W/ 2>/dev/null
if [ -f $W/ray.whl.part00 ] && [ -f $W/ray.whl.part01 ]; then
  cat $W/ray.whl.part00 $W/ray.whl.part01 > $W/ray-2.60.0-cp312-cp312-manylinux2014_x86_64.whl
  (cd $W && sha256sum -c ray.sha256 | sed 's/^/checked: /') || exit 1
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target /tmp/site $W/*.whl
  PYTHONPATH=/tmp/site python3 -c "import ray; print('ray', ray.__version__)"
else
  ls $W
fi
