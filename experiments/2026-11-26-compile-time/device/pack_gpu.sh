#!/usr/bin/env bash
# Make .gpu/ for compile_pets09_gpu.sh: what a PETS09 compile needs on the lent GPU machine beyond its image
# (Python 3.12 with torch, onnx, onnxruntime, opencv, matplotlib, scipy), in under the tool's 64 MiB.
# Run from the repository root with the venv active, after one compile here (it fills anny's cache).
set -euo pipefail
work=$(mktemp -d)
pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux_2_24_x86_64 --platform manylinux_2_17_x86_64 \
    --platform manylinux2014_x86_64 -d "$work/wheels" \
    mitsuba==3.9.1 drjit==1.5.0 OpenImageIO==3.2.2.0 anny==0.6.2 roma==1.8.0 trimesh==5.2.0 pydantic==2.14.4 \
    pydantic_core==2.50.5 annotated_types==0.8.0 typing_inspection shapely==2.2.0 colour-science==0.4.7 \
    astral==3.2 pycocotools==2.0.11
pip wheel -q --no-deps --no-build-isolation -w "$work/wheels" .
mkdir "$work/site"
for wheel in "$work"/wheels/*.whl; do unzip -q -o "$wheel" -d "$work/site"; done
cd "$work/site"
# Pruned to fit: Mitsuba's other variants and unused plugins; its spectral upsampling table (RGB variants never
# read it: renders are byte-identical without it); anny's model sources (its cache below replaces them, and with
# them anny's warp kernels); colour's coverage report; headers.
rm -f mitsuba/*_mono* mitsuba/*_spectral* mitsuba/*polarized* mitsuba/llvm_ad_rgb* mitsuba/data/srgb.coeff
keep=" bitmap box constant cube cylinder diffuse disk hdrfilm independent merge mesh_attribute path perspective \
rectangle srgb directional sunsky envmap twosided principled plastic roughplastic obj ply sphere point spot area \
irregular uniform "
for plugin in mitsuba/plugins/*.so; do name=$(basename "$plugin" .so); [[ $keep == *" $name "* ]] || rm "$plugin"; done
rm -rf anny/data/mpfb2 anny/data/soma anny/data/cached anny/data/faceunits01 anny/examples colour/htmlcov \
    mitsuba/include drjit/include OpenImageIO/bin share
cd - >/dev/null
rm -rf .gpu && mkdir -p .gpu/data
tar -C "$work/site" -cf - . | xz -T2 -9e > .gpu/site.tar.xz
# The two cache entries the renderer's bodies load (the CPU compile's own; keyed by anny's builder arguments).
cache=${ANNY_CACHE_DIR:-$HOME/.cache/anny}
tar -C "$cache" -cf - v14/build_model_data_93dd57e16147875014c822a2d61d80ee.safetensors \
    v14/build_compact_model_data_ecbd9653e239811b7075958b3da1b7af.safetensors | xz -T2 -9e > .gpu/anny_cache.tar.xz
cp ../shared/data/pets09_s2l1/background.png ../shared/data/pets09_s2l1/vtest.avi .gpu/data/
sed -e 's#../../../shared/data/pets09_s2l1/#data/#' scenes/pets09_s2l1/scene.yaml > .gpu/pets09.yaml
grep -qx "/.gpu/" .git/info/exclude 2>/dev/null || echo "/.gpu/" >> .git/info/exclude
rm -rf "$work"
du -sh .gpu
