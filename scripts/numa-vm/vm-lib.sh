# Sourced by the run.sh of both emulated machines (scripts/numa-vm: x86-64; scripts/arm64-vm:
# aarch64): messages, Debian packages fetched once into the work folder, and the initramfs.
# The caller sets `name` (its make target, for messages), `work` (its cache and work folder)
# and `start` (=$SECONDS), and runs under `set -euo pipefail`.

skip() { echo "$name: SKIPPED: $*"; exit 0; }
fail() { echo "$name: FAIL: $*" >&2; exit 1; }
step() { echo "$name: $* ($((SECONDS - start)) s)"; }

# deb_dependency PACKAGE: the versioned package a meta package points at (linux-image-amd64 ->
# linux-image-6.1.0-NN-amd64); empty when apt does not know it.
deb_dependency() {
    apt-cache depends "$1" 2> /dev/null | awk '$1 == "Depends:" && $2 ~ /^linux-image-[0-9]/ { print $2; exit }'
}

# fetch_from_deb PACKAGE MEMBER DEST: downloads Debian's PACKAGE (an exact name, arch-qualified
# where it is another architecture's: a pattern would make apt-get download every package it
# matches) and extracts the files matching MEMBER (a tar wildcard, e.g. './boot/vmlinuz-*') into
# DEST, flattened; nothing is installed. Status 1 with a message when it cannot. (Called in `||`
# lists, where `set -e` is off: every step checks its own status.)
fetch_from_deb() {
    local pkg=$1 member=$2 dest=$3 tmp as_root=no rc
    command -v apt-get > /dev/null && command -v dpkg-deb > /dev/null || return 1
    [ "$(id -u)" -eq 0 ] && as_root=yes
    mkdir -p "$dest"
    tmp=$(mktemp -d "$dest/fetch.XXXXXX") || return 1
    step "downloading $pkg"
    # A stale package index may name a version the mirror no longer has: as root, refresh it once.
    (cd "$tmp" && apt-get download -q -o APT::Sandbox::User="$(id -un)" "$pkg" > /dev/null 2>&1) ||
        { [ $as_root = yes ] && apt-get update -qq > /dev/null 2>&1 &&
            (cd "$tmp" && apt-get download -q -o APT::Sandbox::User=root "$pkg" > /dev/null 2>&1); } &&
        dpkg-deb --fsys-tarfile "$tmp"/*.deb | tar -x -C "$tmp" --wildcards "$member" &&
        find "$tmp" -path "$tmp/${member#./}" -type f -exec mv {} "$dest/" \;
    rc=$?
    rm -rf "$tmp"
    [ $rc -eq 0 ] || echo "$name: could not fetch $pkg"
    return $rc
}

# fetch_kernel META: Debian's kernel that META (linux-image-amd64, linux-image-arm64:arm64) points
# at, its vmlinuz only, into $work/kernel; prints its path. Fetched once, then taken from there.
fetch_kernel() {
    local meta=$1 pkg vmlinuz
    vmlinuz=$(ls "$work"/kernel/vmlinuz-* 2> /dev/null | head -n 1 || true)
    if [ -z "$vmlinuz" ]; then
        pkg=$(deb_dependency "$meta")
        if [ -z "$pkg" ] && [ "$(id -u)" -eq 0 ]; then
            apt-get update -qq > /dev/null 2>&1
            pkg=$(deb_dependency "$meta")
        fi
        [ -n "$pkg" ] || { echo "$name: apt knows no $meta (apt-get update first?)" >&2; return 1; }
        # Another architecture's dependency is qualified (linux-image-6.1.0-NN-arm64:arm64) where apt
        # says so; where it does not, the meta package's qualifier applies.
        case "$meta:$pkg" in *:*:*:*) ;; *:*:*) [ "${meta#*:}" != "$meta" ] && pkg="$pkg:${meta#*:}" ;; esac
        fetch_from_deb "$pkg" './boot/vmlinuz-*' "$work/kernel" >&2 || return 1
        vmlinuz=$(ls "$work"/kernel/vmlinuz-* | head -n 1)
    fi
    echo "$vmlinuz"
}

# pack_initramfs DIR OUT: DIR as a gzip'd cpio archive (the kernel's initramfs format) in OUT.
pack_initramfs() {
    (cd "$1" && find . | cpio -o -H newc --quiet | gzip -1) > "$2"
    step "initramfs $(du -k "$2" | cut -f1) KiB"
}
