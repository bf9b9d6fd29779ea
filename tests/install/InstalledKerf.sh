#!/usr/bin/env bash
# Kerf as a user installs it, run from where it was installed.
#   InstalledKerf.sh prefix   `cmake --install` into a fresh prefix with a space in
#                             its name, then the tree moved elsewhere
#   InstalledKerf.sh deb      the .deb from cpack: its control fields, installed by
#                             dpkg into a fresh root, its files, lintian
# Both run the installed kerf (--version, check, export on an installed example)
# and a helper that prints where the installed program finds its examples.
# Environment: BUILD_DIR, VERSION, HELPER (PrintExamplesDirectory.cpp, built),
# CMAKE, CPACK; KERF_SANITIZE=ON makes the deb mode skip (exit 77).
set -euo pipefail
shopt -s inherit_errexit
mode=$1

fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "-- $*"; }

# expect CODE REGEX COMMAND...: runs COMMAND, checks its exit status and that
# a line of its output (stdout and stderr) matches the extended REGEX.
expect() {
  local code=$1 regex=$2 out status=0
  shift 2
  out=$("$@" 2>&1) || status=$?
  [ "$status" -eq "$code" ] || fail "'$*' exited $status, expected $code; it printed: $out"
  grep -Eq -- "$regex" <<<"$out" || fail "'$*' printed nothing matching '$regex'; it printed: $out"
  printf '%s\n' "$out"
}

# The examples folder the helper, copied into PREFIX/bin, finds from there.
examples_seen_from() {
  local prefix=$1 out
  cp "$HELPER" "$prefix/bin/print-examples-directory"
  out=$(expect 0 "^examples: " "$prefix/bin/print-examples-directory")
  rm "$prefix/bin/print-examples-directory"
  sed -n 's/^examples: //p' <<<"$out"
}

# check_installed PREFIX EXAMPLE: the installed program, on an installed example.
check_installed() {
  local prefix=$1 example=$2 kerf=$1/bin/kerf out triangles bytes seen
  step "installed kerf --version, check, export"
  expect 0 "^kerf $VERSION\$" "$kerf" --version
  expect 0 "valid Kerf document" "$kerf" check "$prefix/share/kerf/examples/$example"
  out=$(expect 0 "part.stl: [0-9,]+ triangles, binary STL" \
    "$kerf" export "$prefix/share/kerf/examples/stool.kerf" -o "$work/part.stl" --feature-size 6)
  printf '%s\n' "$out"
  grep -Eq "as read back: +closed, consistently oriented 2-manifold" <<<"$out" || fail "the exported mesh is not closed"
  # A binary STL is an 84-byte header and count, then 50 bytes a triangle.
  triangles=$(sed -n 's/.*part\.stl: \([0-9,]*\) triangles.*/\1/p' <<<"$out" | tr -d ,)
  bytes=$(stat -c %s "$work/part.stl")
  [ "$bytes" -eq $((84 + 50 * triangles)) ] || fail "part.stl has $bytes bytes, not 84 + 50 x $triangles"

  step "examples found relative to the installed program"
  seen=$(examples_seen_from "$prefix")
  [ "$seen" = "$prefix/share/kerf/examples" ] ||
    fail "installed under $prefix, the program looks for examples in '$seen'"
  [ -f "$seen/side-chair.kerf" ] || fail "the default example is not installed in $seen"
}

# Files every install has, under PREFIX.
check_files() {
  local prefix=$1 size
  step "installed files"
  for f in bin/kerf share/applications/kerf.desktop share/mime/packages/kerf.xml \
           share/man/man1/kerf.1.gz share/icons/hicolor/scalable/apps/kerf.svg \
           share/doc/kerf/copyright share/doc/kerf/changelog.Debian.gz \
           share/kerf/examples/side-chair.kerf share/kerf/examples/stool.kerf; do
    [ -f "$prefix/$f" ] || fail "$f is not installed under $prefix"
  done
  for size in 16 32 48 64 128 256; do
    file "$prefix/share/icons/hicolor/${size}x${size}/apps/kerf.png" | grep -q "PNG image data, $size x $size," ||
      fail "the ${size}x${size} icon is missing or not a $size x $size PNG"
  done
}

case "$mode" in
prefix)
  work=$(realpath "$(mktemp -d "$BUILD_DIR/install-test.XXXXXX")")
  trap 'rm -rf "$work"' EXIT
  prefix="$work/any prefix/opt/kerf"
  step "cmake --install --prefix '$prefix'"
  "$CMAKE" --install "$BUILD_DIR" --prefix "$prefix" >"$work/install.log" 2>&1 ||
    { cat "$work/install.log"; fail "cmake --install failed"; }
  check_files "$prefix"
  check_installed "$prefix" stool.kerf
  step "the install tree, moved, still finds its examples"
  mv "$work/any prefix" "$work/moved"
  seen=$(examples_seen_from "$work/moved/opt/kerf")
  [ "$seen" = "$work/moved/opt/kerf/share/kerf/examples" ] ||
    fail "moved to $work/moved/opt/kerf, the program looks for examples in '$seen'"
  ;;

deb)
  if [ "${KERF_SANITIZE:-OFF}" = "ON" ]; then
    echo "SKIPPED: a sanitizer build is not packaged; tools/test.sh (Release) builds and tests the .deb"
    exit 77
  fi
  work=$(realpath "$(mktemp -d "$BUILD_DIR/package-test.XXXXXX")")
  trap 'rm -rf "$work"' EXIT

  step "cpack -G DEB"
  "$CPACK" -G DEB --config "$BUILD_DIR/CPackConfig.cmake" -B "$work/package" >"$work/cpack.log" 2>&1 ||
    { cat "$work/cpack.log"; fail "cpack could not build the package"; }
  debs=("$work/package"/kerf_*.deb)
  [ ${#debs[@]} -eq 1 ] && [ -f "${debs[0]}" ] || fail "cpack made no single kerf_*.deb: ${debs[*]}"
  deb=${debs[0]}
  echo "$(basename "$deb"), $(stat -c %s "$deb") bytes"

  step "control fields"
  dpkg-deb --field "$deb" Package Version Depends Recommends Section
  [ "$(dpkg-deb --field "$deb" Package)" = kerf ] || fail "the package is not named kerf"
  [[ "$(dpkg-deb --field "$deb" Version)" == "$VERSION"-* ]] || fail "the package version is not $VERSION-REVISION"
  depends=$(dpkg-deb --field "$deb" Depends)
  depended_on=$(sed 's/([^)]*)//g; s/[|,]/ /g' <<<"$depends" | tr -s ' ' '\n')
  # Read off the binary by dpkg-shlibdeps: oneTBB, OpenMesh, the Vulkan loader.
  for package in libtbb12 libopenmesh1 libvulkan1 libstdc++6; do
    grep -qxF "$package" <<<"$depended_on" || fail "Depends lacks $package: $depends"
  done
  grep -q "mesa-vulkan-drivers" <<<"$(dpkg-deb --field "$deb" Recommends)" ||
    fail "Recommends lacks mesa-vulkan-drivers"

  step "dpkg --install into a fresh root"
  # The root's package database holds only what kerf depends on, copied from
  # this machine's, so dpkg checks the dependencies and their versions.
  root=$work/root admin=$work/dpkg
  mkdir -p "$root" "$admin/info" "$admin/updates" "$admin/triggers"
  : >"$admin/status"
  : >"$admin/available"
  for package in $depended_on; do
    if dpkg-query --status "$package" >>"$admin/status" 2>/dev/null; then
      echo >>"$admin/status"
      : >"$admin/info/$(dpkg-query --show --showformat='${binary:Package}' "$package").list"
    fi
  done
  dpkg --admindir="$admin" --instdir="$root" --force-not-root --force-bad-path --no-triggers \
    --install "$deb" >"$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log"; fail "dpkg could not install the package"; }
  cat "$work/dpkg.log"
  dpkg-query --admindir="$admin" --show --showformat='${Status}' kerf | grep -q "install ok installed" ||
    fail "dpkg does not list kerf as installed"
  dpkg-query --admindir="$admin" --listfiles kerf | grep -qx /usr/bin/kerf || fail "dpkg lists no /usr/bin/kerf"

  check_files "$root/usr"
  check_installed "$root/usr" side-chair.kerf

  step "the manual page"
  man_text=$(MANWIDTH=100 man --warnings -l "$root/usr/share/man/man1/kerf.1.gz" 2>"$work/man.err")
  [ ! -s "$work/man.err" ] || { cat "$work/man.err"; fail "man warns about kerf.1"; }
  for heading in NAME SYNOPSIS "kerf check" "kerf export" "kerf render" FILES; do
    grep -q "^ *$heading" <<<"$man_text" || fail "the manual page has no '$heading'"
  done

  step "the desktop entry and the MIME type"
  desktop=$root/usr/share/applications/kerf.desktop
  desktop-file-validate "$desktop" || fail "desktop-file-validate rejects kerf.desktop"
  grep -qx "Exec=kerf %f" "$desktop" || fail "the desktop entry does not run 'kerf %f'"
  grep -qx "Icon=kerf" "$desktop" || fail "the desktop entry's icon is not 'kerf'"
  grep -q "^MimeType=.*application/x-kerf;" "$desktop" || fail "the desktop entry does not open application/x-kerf"
  # What shared-mime-info's trigger does on a real install, on a copy.
  cp -r "$root/usr/share/mime" "$work/mime"
  update-mime-database "$work/mime" >/dev/null
  grep -qx "[0-9]*:application/x-kerf:\*\.kerf" "$work/mime/globs2" || fail "*.kerf is not application/x-kerf"
  grep -q "<icon name=\"kerf\"/>" "$work/mime/application/x-kerf.xml" || fail "application/x-kerf has not Kerf's icon"

  step "lintian"
  # Errors fail the test; warnings and notes are printed.
  lintian --fail-on error --display-info "$deb" 2>&1 || fail "lintian reports errors on $(basename "$deb")"
  ;;

*)
  fail "unknown mode '$mode' (prefix or deb)"
  ;;
esac
echo "ok"
