# on the device (carry .whl), once: build gsplat's CUDA extension and return it, so that later machines unpack it in
# 5 s instead of building it for 77 s (run9/recv.sh does, when the call carries .gsplat_build). Here afterwards:
#   mkdir -p .gsplat_build && cp FILES_AT/gsplat_build.tgz .gsplat_build/gsplat_build_cu130_py312.tgz
#   echo /.gsplat_build/ >> .git/info/exclude
# (torch 2.11.0+cu130, Python 3.12, gsplat 1.5.3: 7.2 MB; torch checks the sources' hash and rebuilds if they differ)
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl
export PYTHONPATH=/tmp/site:.
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1
d=$(python3 -c "import torch.utils.cpp_extension as c; print(c._get_build_directory('gsplat_cuda', False))")
tar czf $OUT/gsplat_build.tgz -C $(dirname $d) $(basename $d)
