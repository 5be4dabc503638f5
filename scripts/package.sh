#!/usr/bin/env bash
# Build telerehab's Debian package and a portable tar.gz into target/debian/ (issue 27).
#   bash scripts/package.sh                       # cargo build --release, then package
#   bash scripts/package.sh --binary PATH         # package a binary built already (CI: debug)
#   bash scripts/package.sh --out DIR             # somewhere else than target/debian
# Hand-staged and built with dpkg-deb (no cargo-deb to install). Needs dpkg-dev (dpkg-shlibdeps),
# binutils (strip), python3 and cargo (the copyright file is generated from `cargo metadata`);
# scripts/setup.sh installs them. What the package holds: packaging/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

BIN=""
OUT="$ROOT/target/debian"
while [ $# -gt 0 ]; do
  case "$1" in
    --binary) BIN="$2"; shift 2 ;;
    --out) OUT="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "package.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
if [ -z "$BIN" ]; then
  cargo build --release -p telerehab
  BIN="${CARGO_TARGET_DIR:-$ROOT/target}/release/telerehab"
fi
[ -x "$BIN" ] || { echo "package.sh: no executable at $BIN" >&2; exit 2; }
mkdir -p "$OUT"; OUT="$(cd "$OUT" && pwd)"

VERSION="$("$BIN" --version | awk '{print $2}')"
ARCH="$(dpkg --print-architecture)"
NAME="telerehab_${VERSION}_${ARCH}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
S="$WORK/root"   # the staged tree, as installed
echo "package.sh: telerehab $VERSION ($ARCH) from $BIN"

# Files, with their modes (root-owned: dpkg-deb --root-owner-group).
install -D -m 0755 "$BIN" "$S/usr/bin/telerehab"
strip --strip-unneeded --remove-section=.comment --remove-section=.note "$S/usr/bin/telerehab"
install -D -m 0644 packaging/udev/70-telerehab.rules "$S/usr/lib/udev/rules.d/70-telerehab.rules"
install -D -m 0644 packaging/telerehab-hub.service "$S/usr/lib/systemd/system/telerehab-hub.service"
install -D -m 0644 packaging/telerehab-hub.sysusers "$S/usr/lib/sysusers.d/telerehab-hub.conf"
install -D -m 0644 packaging/telerehab-hub.tmpfiles "$S/usr/lib/tmpfiles.d/telerehab-hub.conf"
install -D -m 0644 packaging/hub.env "$S/etc/telerehab/hub.env"
install -D -m 0644 packaging/telerehab.desktop "$S/usr/share/applications/telerehab.desktop"
install -D -m 0644 packaging/telerehab.svg "$S/usr/share/icons/hicolor/scalable/apps/telerehab.svg"
if command -v rsvg-convert >/dev/null 2>&1; then
  mkdir -p "$S/usr/share/icons/hicolor/256x256/apps"
  rsvg-convert -w 256 -h 256 packaging/telerehab.svg \
    -o "$S/usr/share/icons/hicolor/256x256/apps/telerehab.png"
  chmod 0644 "$S/usr/share/icons/hicolor/256x256/apps/telerehab.png"
fi

# Man pages and completions, from the CLI itself.
"$S/usr/bin/telerehab" docs --out "$WORK/docs" >/dev/null
install -d -m 0755 "$S/usr/share/man/man1"
for page in "$WORK"/docs/man1/*.1; do
  gzip -9n -c "$page" > "$S/usr/share/man/man1/$(basename "$page").gz"
done
chmod 0644 "$S"/usr/share/man/man1/*.gz
C="$WORK/docs/completions"
install -D -m 0644 "$C/telerehab.bash" "$S/usr/share/bash-completion/completions/telerehab"
install -D -m 0644 "$C/_telerehab" "$S/usr/share/zsh/vendor-completions/_telerehab"
install -D -m 0644 "$C/telerehab.fish" "$S/usr/share/fish/vendor_completions.d/telerehab.fish"

# /usr/share/doc: the generated copyright and a changelog (a native package's: changelog.gz).
D="$S/usr/share/doc/telerehab"
install -d -m 0755 "$D"
python3 scripts/gen_copyright.py --out "$D/copyright"
DATE="$(date -R -d "@$(git log -1 --format=%ct 2>/dev/null || date +%s)")"
printf '%s\n' "telerehab ($VERSION) unstable; urgency=medium" "" \
  "  * Built from commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown) of the" \
  "    telerehab repository (upstream release; see its git history)." "" \
  " -- telerehab developers <telerehab@example.invalid>  $DATE" \
  | gzip -9n > "$D/changelog.gz"
chmod 0644 "$D"/*

# DEBIAN/: scripts, conffiles, control (Depends from the binary's NEEDED entries + the
# graphics and windowing libraries it loads at run time: wgpu's Vulkan and EGL/GL, winit's X11
# and Wayland).
install -d -m 0755 "$S/DEBIAN"
for s in postinst prerm postrm; do install -m 0755 "packaging/debian/$s" "$S/DEBIAN/$s"; done
echo "/etc/telerehab/hub.env" > "$S/DEBIAN/conffiles"
mkdir -p "$WORK/shlibs/debian"
printf 'Source: telerehab\n\nPackage: telerehab\nArchitecture: any\n' > "$WORK/shlibs/debian/control"
SHLIBS="$(cd "$WORK/shlibs" && dpkg-shlibdeps -O "$S/usr/bin/telerehab" 2>/dev/null \
  | sed -n 's/^shlibs:Depends=//p')"
RUNTIME="libvulkan1, mesa-vulkan-drivers | vulkan-icd, libegl1, libegl-mesa0, libgl1-mesa-dri"
WINDOW="libx11-6, libx11-xcb1, libxcursor1, libxi6, libxkbcommon0, libxkbcommon-x11-0"
# The patient's voice: espeak-ng speaks each page's main sentence (the program, run by name).
VOICE="espeak-ng"
# The window's fonts for scripts beyond Latin (crates/render/src/fonts.rs reads them by path).
FONTS="fonts-noto-core, fonts-noto-cjk"
SIZE_KB="$(du -sk --exclude=DEBIAN "$S" | cut -f1)"
cat > "$S/DEBIAN/control" <<EOF
Package: telerehab
Version: $VERSION
Architecture: $ARCH
Maintainer: telerehab developers <telerehab@example.invalid>
Installed-Size: $SIZE_KB
Depends: $SHLIBS, $RUNTIME, $WINDOW, $VOICE, $FONTS
Recommends: libwayland-client0, libwayland-egl1
Suggests: postgresql
Section: science
Priority: optional
Description: home driving rehabilitation station and clinic hub
 telerehab turns a force-feedback steering wheel and motion sensors on the arms
 into a rehabilitation station for people recovering from a stroke: road and
 dial exercises the clinic prescribes, haptic guidance that adapts to the
 patient, and a recording of every session.
 .
 The same program is the clinic's hub (telerehab-hub.service, not enabled by
 default): it pairs stations over mutual TLS, stores their sessions and serves
 the therapists' console. Run "telerehab doctor" to check a station's wheel,
 sensors, permissions and graphics.
EOF

(cd "$S" && find . -path ./DEBIAN -prune -o -path ./etc -prune -o -type f -printf '%P\0' \
  | LC_ALL=C sort -z | xargs -0 md5sum) > "$S/DEBIAN/md5sums"
chmod 0644 "$S/DEBIAN/md5sums" "$S/DEBIAN/control" "$S/DEBIAN/conffiles"

# The .deb.
DEB="$OUT/$NAME.deb"
dpkg-deb --build --root-owner-group -Zxz "$S" "$DEB" >/dev/null
rm -rf "$S/DEBIAN"
echo "package.sh: $DEB ($(du -k "$DEB" | cut -f1) kB; installed $SIZE_KB kB)"

# The portable tar.gz: the same files under one directory, and how to install them by hand.
T="$WORK/telerehab-$VERSION-$ARCH"
mkdir -p "$T/man1"
cp "$S/usr/bin/telerehab" packaging/udev/70-telerehab.rules packaging/telerehab.desktop \
  packaging/telerehab.svg packaging/telerehab-hub.service packaging/telerehab-hub.sysusers \
  packaging/telerehab-hub.tmpfiles packaging/hub.env "$T/"
cp "$S"/usr/share/man/man1/*.gz "$T/man1/"
cp -r "$C" "$T/completions"
cp packaging/INSTALL.md "$T/INSTALL.md"
cp "$D/copyright" "$T/COPYRIGHT"
TAR="$OUT/telerehab-$VERSION-$ARCH.tar.gz"
tar -C "$WORK" --owner=0 --group=0 --numeric-owner --sort=name -czf "$TAR" "$(basename "$T")"
echo "package.sh: $TAR ($(du -k "$TAR" | cut -f1) kB)"
