# here, from the repository root: the wheels the device lacks (Python 3.12 there), into .whl/ (16 MB, git-ignored)
echo /.whl/ >> .git/info/exclude
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64 \
  --platform manylinux2014_x86_64 -d .whl gsplat==1.5.3 jaxtyping wadler-lindig plyfile==1.1.5 OpenImageIO==3.2.2.0 \
  rich markdown-it-py mdurl pygments
