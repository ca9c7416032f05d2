# Sourced by the device scripts, from the repository root: unpacks .gpu/ (pack_gpu.sh) once per machine into
# /tmp and points Python and anny at it.
export PYTHONUNBUFFERED=1
site=/tmp/vc-site
if [ ! -f "$site/vc/__init__.py" ]; then
    mkdir -p "$site" /tmp/anny-cache
    tar -xJf .gpu/site.tar.xz -C "$site" && tar -xJf .gpu/anny_cache.tar.xz -C /tmp/anny-cache || exit 1
fi
export PYTHONPATH=$site ANNY_CACHE_DIR=/tmp/anny-cache
# The program of the vc-TOOL command, for `python3 -c "$(vc_main TOOL)" ARGS` (the site's wheel is unpacked, not
# installed: it has no console scripts).
vc_main() { printf "import sys; from vc.cli.%s import main; sys.argv[0] = 'vc-%s'; sys.exit(main())" "$1" "$1"; }
