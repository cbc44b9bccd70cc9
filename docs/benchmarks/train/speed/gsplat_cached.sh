# On the device, after the wheels are installed in /tmp/site: unpack gsplat's CUDA extension built on an earlier
# machine (docs/benchmarks/effects/run12/gsplat_build.sh; carry .gsplat_build) so that the first import loads it
# in seconds instead of building it (77 s).
# Why the sources are dated back instead of the objects touched: ninja rebuilds an object whose *logged* mtime
# (.ninja_log, written on the building machine) is older than a source's, and whose dependency record
# (.ninja_deps) is older than the object itself. Touching the objects broke the second rule and could not fix
# the first; the sources pip just installed are the only files that are newer than they should be.
G=/root/.cache/torch_extensions/py312_cu130
[ -f .gsplat_build/gsplat_build_cu130_py312.tgz ] || exit 0
[ -d $G/gsplat_cuda ] || { mkdir -p $G && tar xzf .gsplat_build/gsplat_build_cu130_py312.tgz -C $G; }
find /tmp/site/gsplat -type f -exec touch -d 2020-01-01 {} +
command -v ninja > /dev/null && (cd $G/gsplat_cuda && ninja -n -d explain 2>&1 | head -5)
