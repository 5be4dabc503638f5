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
  # wineboot's wineserver lingers a few seconds, and its desktop has whatever display wineboot
  # had (none, outside xvfb-run): a program started under a display before it exits joins that
  # desktop and can make no window ("no driver could be loaded"). Wait for it to end.
  wineserver -w
}

wine_prefix_end() {
  wineserver -k >/dev/null 2>&1 || true
}
