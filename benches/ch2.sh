# Sourced by benches/peer.sh (for bench.sh, lanes.sh and projections.sh): ch2(), the path of
# ch2.nii.gz (the Colin27 T1 from Debian's mricron-data, BSD-3), fetched with apt-get download
# the first time.

ch2() {
    local cache=${XDG_CACHE_HOME:-$HOME/.cache}/voxcast
    if [ ! -f "$cache/ch2.nii.gz" ]; then
        mkdir -p "$cache/deb"
        (cd "$cache/deb" && apt-get download mricron-data >/dev/null)
        dpkg -x "$cache"/deb/mricron-data_*.deb "$cache/deb/x"
        cp "$cache/deb/x/usr/share/mricron/templates/ch2.nii.gz" "$cache/"
        rm -rf "$cache/deb"
    fi
    echo "$cache/ch2.nii.gz"
}
