#!/usr/bin/env bash
# The MeshLab filter plugin against MeshLab 2022.02 (FilterPlugin), in the
# Debian trixie chroot that the Blender tests use (.ci/blender43;
# VN_TRIXIE_ROOT, default /var/cache/vn/trixie): compiles the same
# filter_vn.cpp with VN_MESHLAB_API=2022 against src/common and vcglib of
# trixie's meshlab source package, links it with -Wl,--no-undefined against
# trixie's libmeshlab-common.so, then loads it as MeshLab does
# (tests/meshlab/load_filter_plugin.cpp: IID, version and scalar check, class,
# parameters, every method on a small mesh, a bad method's MLException).
#
# The first run installs the compiler, Qt 5 / GLEW / Eigen headers and meshlab
# into the chroot (about 30 s) and fetches the source once (private apt lists
# under /var/tmp/vn-meshlab in the chroot; the chroot's apt sources are not
# changed). Exit 77 (skipped) when the chroot does not exist. Needs root or sudo.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
root=${VN_TRIXIE_ROOT:-/var/cache/vn/trixie}
SUDO=; [ "$(id -u)" -eq 0 ] || SUDO=sudo
if [ ! -f "$root/.vn-ready" ]; then
	echo "SKIP: no trixie chroot in $root (bash .ci/blender43 --setup creates it)"; exit 77
fi
inroot() { $SUDO chroot "$root" env LC_ALL=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"; }

pkgs=(g++ pkgconf qtbase5-dev qtbase5-dev-tools libqt5opengl5-dev libglew-dev libeigen3-dev meshlab xz-utils)
missing=()
for p in "${pkgs[@]}"; do
	inroot dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
	echo "check-meshlab2022: installing ${missing[*]} into the chroot" >&2
	inroot apt-get update -qq
	inroot apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

w=/var/tmp/vn-meshlab
if [ ! -f "$root$w/sdk/.complete" ]; then
	echo "check-meshlab2022: fetching trixie's meshlab source package" >&2
	$SUDO mkdir -p "$root$w/lists/partial"
	suite=$(inroot sh -c '. /etc/os-release && echo "$VERSION_CODENAME"')
	echo "deb-src http://deb.debian.org/debian ${suite:-trixie} main" | $SUDO tee "$root$w/src.list" >/dev/null
	O="-o Dir::Etc::SourceList=$w/src.list -o Dir::Etc::SourceParts=/dev/null -o Dir::State::Lists=$w/lists -o APT::Sandbox::User=root"
	inroot sh -c "cd $w && apt-get $O update -qq && (apt-get $O source --download-only -qq meshlab >/dev/null 2>&1 || true)"
	orig=$(ls "$root$w"/meshlab_*.orig.tar.* 2>/dev/null | head -n1 || true)
	[ -n "$orig" ] || { echo "FAIL: could not download trixie's meshlab source"; exit 1; }
	$SUDO rm -rf "$root$w/sdk" && $SUDO mkdir -p "$root$w/sdk"
	$SUDO tar -xf "$orig" -C "$root$w/sdk" --strip-components=1 --wildcards '*/src/common/*' '*/src/vcglib/*' '*/ML_VERSION'
	$SUDO touch "$root$w/sdk/.complete"
fi

# This source tree: the library's C files, the plugin, the loader, in a
# build folder of this run's own (runs from several worktrees may overlap).
b=$w/build-$$
trap '$SUDO rm -rf "$root$b"' EXIT
$SUDO rm -rf "$root$b" && $SUDO mkdir -p "$root$b"
$SUDO cp -r "$src/src" "$root$b/vnsrc"
$SUDO cp "$src"/filters/meshlab/*.h "$src"/filters/meshlab/*.cpp "$src/tests/meshlab/load_filter_plugin.cpp" "$root$b/"
inroot sh -ec "
cd $b
ver=\$(tr -d ' \n' < ../sdk/ML_VERSION)
echo \"check-meshlab2022: MeshLab \$ver SDK, \$(dpkg-query -W -f='\${Version}' meshlab) installed, \$(g++ --version | head -n1)\"
defs=\"-DMESHLAB_SCALAR=float -DMESHLAB_VERSION=\$ver -DVN_MESHLAB_API=2022\"
inc=\"-isystem ../sdk/src -isystem ../sdk/src/vcglib -isystem /usr/include/eigen3 -Ivnsrc \$(pkg-config --cflags Qt5Widgets Qt5OpenGL Qt5Xml)\"
libs=\"/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so \$(pkg-config --libs Qt5Widgets Qt5OpenGL Qt5Xml) -pthread -lm\"
for c in vnsrc/*.c; do gcc -std=c11 -O2 -fPIC -fvisibility=hidden -ffp-contract=off -c \"\$c\" -o \"\${c%.c}.o\"; done
/usr/lib/qt5/bin/moc \$defs \$(echo \$inc | sed 's/-isystem /-I/g') filter_vn.h -o moc_filter_vn.cpp
g++ -std=c++17 -O2 -fPIC -Wall -Wextra \$defs \$inc -shared -o libfilter_vn.so filter_vn.cpp moc_filter_vn.cpp vnsrc/*.o \\
	-Wl,--no-undefined \$libs
echo 'ok   libfilter_vn.so compiled and linked (-Wl,--no-undefined) against MeshLab 2022 FilterPlugin'
g++ -std=c++17 -O1 -fPIC \$defs \$inc -o load_filter_plugin load_filter_plugin.cpp \$libs \\
	-Wl,-rpath,/usr/lib/x86_64-linux-gnu/meshlab
QT_QPA_PLATFORM=offscreen ./load_filter_plugin \$PWD/libfilter_vn.so
"
