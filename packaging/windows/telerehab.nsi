; telerehab's Windows installer (issue 46): telerehab-setup-<version>.exe, built on Linux with
; NSIS by scripts/package-windows.sh, which stages the files and passes these defines:
;   VERSION      the workspace's version (Cargo.toml), e.g. 0.1.0
;   STAGE        a directory holding telerehab.exe (stripped), telerehab.ico, COPYRIGHT.txt and
;                langstrings.nsh (the installer's own words from crates/i18n/locales/*/installer.ftl)
;   OUTFILE      the installer to write
;   SIGN         (optional) a command that signs the file named by %1 (e.g. osslsigncode): the
;                installer and its uninstaller are signed as they are written
;
; Per user, no administrator: %LOCALAPPDATA%\Programs\telerehab, the user's Start menu, the
; uninstaller under HKCU's Uninstall key. The station's home (pairing, settings.toml,
; recordings) is %APPDATA%\telerehab\config, made by telerehab itself on its first run; the
; uninstaller leaves it (the patient's data and the clinic's pairing), packaging/INSTALL.md
; says how to remove it.

!macro NEEDS NAME
  !ifndef ${NAME}
    !error "${NAME} is not defined: build with scripts/package-windows.sh"
  !endif
!macroend
!insertmacro NEEDS VERSION
!insertmacro NEEDS STAGE
!insertmacro NEEDS OUTFILE

; A 64-bit installer for a 64-bit program (it runs where telerehab.exe can, and under a 64-bit-only
; Wine such as Debian's wine64 without wine32, where NSIS's default x86 stub does not start).
Target amd64-unicode
SetCompressor /SOLID lzma
ManifestDPIAware true
RequestExecutionLevel user

!define APP "telerehab"
!define PUBLISHER "telerehab developers"
!define UNINSTALL_KEY "Software\Microsoft\Windows\CurrentVersion\Uninstall\${APP}"

Name "${APP}"
OutFile "${OUTFILE}"
InstallDir "$LOCALAPPDATA\Programs\${APP}"
InstallDirRegKey HKCU "${UNINSTALL_KEY}" "InstallLocation"
BrandingText "${APP} ${VERSION}"

!ifdef SIGN
  !finalize '${SIGN}'
  !uninstfinalize '${SIGN}'
!endif

; The file's properties (Explorer's Details tab). VIProductVersion wants four numbers.
VIProductVersion "${VERSION}.0"
VIAddVersionKey /LANG=0 "ProductName" "${APP}"
VIAddVersionKey /LANG=0 "ProductVersion" "${VERSION}"
VIAddVersionKey /LANG=0 "FileVersion" "${VERSION}"
VIAddVersionKey /LANG=0 "FileDescription" "${APP} ${VERSION} setup"
VIAddVersionKey /LANG=0 "CompanyName" "${PUBLISHER}"
VIAddVersionKey /LANG=0 "LegalCopyright" "${PUBLISHER}"

!include "MUI2.nsh"

!define MUI_ICON "${STAGE}\telerehab.ico"
!define MUI_UNICON "${STAGE}\telerehab.ico"
!define MUI_ABORTWARNING

; Few pages for a patient: what is installed, then done. No folder to choose (per user, the
; standard place) and no licence to accept (COPYRIGHT.txt is installed beside the program).
!insertmacro MUI_PAGE_WELCOME
!insertmacro MUI_PAGE_INSTFILES
!define MUI_FINISHPAGE_TEXT "$(FINISH_TEXT)"
; "Run telerehab" (NSIS's own words), ticked: as the Start-menu entry, its console minimised.
!define MUI_FINISHPAGE_RUN
!define MUI_FINISHPAGE_RUN_FUNCTION RunTelerehab
!insertmacro MUI_PAGE_FINISH

!insertmacro MUI_UNPAGE_CONFIRM
!insertmacro MUI_UNPAGE_INSTFILES

; The patient's language where NSIS has it (it picks the one of Windows' display language);
; English first: the fallback for every other.
!insertmacro MUI_LANGUAGE "English"
!insertmacro MUI_LANGUAGE "German"
!insertmacro MUI_LANGUAGE "Spanish"
!insertmacro MUI_LANGUAGE "SimpChinese"
!include "${STAGE}\langstrings.nsh"

Function RunTelerehab
  ExecShell "" "$INSTDIR\telerehab.exe" "" SW_SHOWMINIMIZED
FunctionEnd

Section "telerehab"
  SetShellVarContext current
  SetOutPath "$INSTDIR"
  File "${STAGE}\telerehab.exe"
  File "${STAGE}\telerehab.ico"
  File "${STAGE}\COPYRIGHT.txt"
  WriteUninstaller "$INSTDIR\uninstall.exe"

  ; The patient's entry in the Start menu: telerehab with no arguments is the patient window's
  ; first run (as packaging/telerehab.desktop on Linux). telerehab.exe is a console program:
  ; its console window starts minimised, the patient sees the patient window.
  CreateShortcut "$SMPROGRAMS\${APP}.lnk" "$INSTDIR\telerehab.exe" "" \
    "$INSTDIR\telerehab.ico" 0 SW_SHOWMINIMIZED "" "$(SHORTCUT_COMMENT)"

  ; Settings > Apps lists it, and removes it, for this user only.
  WriteRegStr HKCU "${UNINSTALL_KEY}" "DisplayName" "${APP}"
  WriteRegStr HKCU "${UNINSTALL_KEY}" "DisplayVersion" "${VERSION}"
  WriteRegStr HKCU "${UNINSTALL_KEY}" "Publisher" "${PUBLISHER}"
  WriteRegStr HKCU "${UNINSTALL_KEY}" "DisplayIcon" "$INSTDIR\telerehab.ico"
  WriteRegStr HKCU "${UNINSTALL_KEY}" "InstallLocation" "$INSTDIR"
  WriteRegStr HKCU "${UNINSTALL_KEY}" "UninstallString" '"$INSTDIR\uninstall.exe"'
  WriteRegStr HKCU "${UNINSTALL_KEY}" "QuietUninstallString" '"$INSTDIR\uninstall.exe" /S'
  WriteRegDWORD HKCU "${UNINSTALL_KEY}" "NoModify" 1
  WriteRegDWORD HKCU "${UNINSTALL_KEY}" "NoRepair" 1
  ; EstimatedSize in KiB: the installed files.
  SectionGetSize 0 $0
  WriteRegDWORD HKCU "${UNINSTALL_KEY}" "EstimatedSize" $0
SectionEnd

Section "Uninstall"
  SetShellVarContext current
  Delete "$SMPROGRAMS\${APP}.lnk"
  Delete "$INSTDIR\telerehab.exe"
  Delete "$INSTDIR\telerehab.ico"
  Delete "$INSTDIR\COPYRIGHT.txt"
  Delete "$INSTDIR\uninstall.exe"
  RMDir "$INSTDIR"
  DeleteRegKey HKCU "${UNINSTALL_KEY}"
  ; %APPDATA%\telerehab (pairing, settings, recordings not yet sent) stays: the patient's data.
SectionEnd
