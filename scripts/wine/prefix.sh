# A throwaway Wine prefix for running telerehab.exe and Windows tests here (issue 46). Source it,
# then call `wine_prefix DIR`: exports WINEPREFIX=DIR (quiet, no Mono or Gecko prompts), makes the
# prefix and installs the bcryptprimitives.dll shim into it (Wine 8, Debian 12, lacks that DLL,
# where Rust's std draws random numbers on Windows 8 and later: scripts/wine/bcryptprimitives.c).
# `wine_prefix_end` stops the prefix's wineserver. Used by scripts/windows.sh and
# scripts/test_windows_installer.sh.
WINE_SHIM_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

wine_prefix() {
  export WINEPREFIX="$1" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
  wineboot --init >/dev/null 2>&1 || { echo "wine_prefix: wineboot could not make a prefix in $1" >&2; return 1; }
  local dll="$WINEPREFIX/drive_c/windows/system32/bcryptprimitives.dll"
  if [ ! -e "$dll" ]; then
    x86_64-w64-mingw32-gcc -O2 -shared -o "$dll" \
      "$WINE_SHIM_DIR/bcryptprimitives.c" "$WINE_SHIM_DIR/bcryptprimitives.def" -ladvapi32
  fi
}

wine_prefix_end() {
  wineserver -k >/dev/null 2>&1 || true
}
