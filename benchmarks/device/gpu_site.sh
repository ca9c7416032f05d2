# Sourced by the device scripts, from the repository root: unpacks .gpu/ (pack_gpu.sh) once per machine into
# /tmp and points Python and anny at it.
export PYTHONUNBUFFERED=1
site=/tmp/vc-site
if [ ! -f "$site/vc/__init__.py" ]; then
    mkdir -p "$site" /tmp/anny-cache
    tar -xJf .gpu/site.tar.xz -C "$site" && tar -xJf .gpu/anny_cache.tar.xz -C /tmp/anny-cache || exit 1
fi
export PYTHONPATH=$site ANNY_CACHE_DIR=/tmp/anny-cache
