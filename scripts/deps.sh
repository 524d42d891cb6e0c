#!/bin/sh
# Install the Debian packages named on the command line that are not installed
# yet.  Runs apt-get (update first) as root, or through sudo otherwise; does
# nothing at all when every package is present.
set -u
missing=""
for pkg in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $pkg"
    fi
done
[ -z "$missing" ] && exit 0

echo "deps: installing$missing" >&2
if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
else
    echo "deps: missing packages:$missing; run as root or install sudo" >&2
    exit 2
fi
$SUDO apt-get update -qq || { echo "deps: apt-get update failed" >&2; exit 1; }
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing ||
    { echo "deps: apt-get install failed for:$missing" >&2; exit 1; }
