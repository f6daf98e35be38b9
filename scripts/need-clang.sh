# Sourced by sanitize-test.sh and fuzz-run.sh: the sanitizer tree (the `asan`
# preset) is built with clang, whose libFuzzer its fuzz targets need; installs
# Debian's clang 14 and its runtime libraries if they are missing.
need_clang() {
  local packages=(clang libclang-rt-dev) missing=() p sudo=""
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "installing ${missing[*]}"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}
