# Sourced by the scripts of tests/gpu: install_missing PACKAGE... installs the Debian packages
# among those given that are not installed yet (as root, or through sudo), as setup.sh does
# for the build's own. Returns non-zero when apt-get fails.
install_missing() {
  local missing=() pkg sudo=""
  for pkg in "$@"; do
    [[ $(dpkg-query -W -f='${Status}' "$pkg" 2> /dev/null) == *"install ok installed"* ]] || missing+=("$pkg")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing Debian's ${missing[*]}"
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" > /dev/null
}
