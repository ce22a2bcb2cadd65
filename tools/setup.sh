# Shared set-up helpers for tools/sbt, tools/mapm and .ci/run (sourced, not run).
# Each function prints a one-line error and exits non-zero when it cannot do its job.

MAPM_SBT_LAUNCH_VERSION="${MAPM_SBT_LAUNCH_VERSION:-1.10.7}"
MAPM_CACHE="${MAPM_CACHE:-$HOME/.cache/mapm}"

mapm_die() { echo "mapm setup: $*" >&2; exit 1; }

mapm_ensure_java() {
  command -v java >/dev/null 2>&1 || mapm_die "java not found: install a JDK 17 (apt-get install openjdk-17-jdk-headless)"
}

# apt-get install PACKAGE... when we are root and apt is present; otherwise a clear error.
mapm_apt_install() {
  if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1; then
    mapm_die "cannot install '$*' (need root and apt-get); install it by hand"
  fi
  echo "mapm setup: installing $* from Debian's packages ..." >&2
  if ! { apt-get install -y -qq "$@" >/dev/null 2>&1 || { apt-get update -qq >/dev/null 2>&1 && apt-get install -y -qq "$@" >/dev/null 2>&1; }; }; then
    mapm_die "apt-get install $* failed; install it by hand"
  fi
}

mapm_ensure_verilator() {
  [ "${MAPM_SKIP_VERILATOR:-0}" = 1 ] && return 0
  command -v verilator >/dev/null 2>&1 || mapm_apt_install verilator
  # ccache only speeds up rebuilds: a machine that cannot install it goes on without it.
  command -v ccache >/dev/null 2>&1 || ( mapm_apt_install ccache ) || echo "mapm setup: going on without ccache" >&2
}

# Prints the path of the sbt launcher jar, fetching it through Maven the first time.
mapm_sbt_launcher() {
  local jar="$MAPM_CACHE/sbt-launch-$MAPM_SBT_LAUNCH_VERSION.jar"
  if [ ! -s "$jar" ]; then
    command -v mvn >/dev/null 2>&1 || mapm_apt_install maven
    mkdir -p "$MAPM_CACHE"
    echo "mapm setup: fetching org.scala-sbt:sbt-launch:$MAPM_SBT_LAUNCH_VERSION through Maven ..." >&2
    mvn -q -B dependency:copy -Dartifact="org.scala-sbt:sbt-launch:$MAPM_SBT_LAUNCH_VERSION" \
      -DoutputDirectory="$MAPM_CACHE" >&2 || mapm_die "could not fetch sbt-launch through Maven"
    [ -s "$jar" ] || mapm_die "sbt-launch jar missing after Maven fetch: $jar"
  fi
  echo "$jar"
}
