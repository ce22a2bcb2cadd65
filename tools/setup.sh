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
  # Waits for dpkg's lock (up to 10 minutes) rather than failing while another install runs.
  local wait=(-o DPkg::Lock::Timeout=600)
  if ! { apt-get install "${wait[@]}" -y -qq "$@" >/dev/null 2>&1 || { apt-get update "${wait[@]}" -qq >/dev/null 2>&1 && apt-get install "${wait[@]}" -y -qq "$@" >/dev/null 2>&1; }; }; then
    mapm_die "apt-get install $* failed; install it by hand"
  fi
}

mapm_ensure_verilator() {
  [ "${MAPM_SKIP_VERILATOR:-0}" = 1 ] && return 0
  command -v verilator >/dev/null 2>&1 || mapm_apt_install verilator
  # ccache only speeds up rebuilds: a machine that cannot install it goes on without it.
  command -v ccache >/dev/null 2>&1 || ( mapm_apt_install ccache ) || echo "mapm setup: going on without ccache" >&2
}

# valgrind, for the instruction counts of `mapm bench-sim`; prints valgrind=PATH.
mapm_ensure_valgrind() {
  command -v valgrind >/dev/null 2>&1 || mapm_apt_install valgrind
  echo "valgrind=$(command -v valgrind)"
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

# The open cost flow (tools/mapm cost): yosys through PyPI's pyosys (a native wheel with yosys-abc
# inside) in a venv under the cache, OpenSTA from Debian, and the OSU 0.18 um cells from Debian's
# qflow-tech-osu018 (unpacked from the .deb alone, without qflow). Each prints the one path it made.
MAPM_PYOSYS_VERSION="${MAPM_PYOSYS_VERSION:-0.70}"
MAPM_FLIP_VERSION="${MAPM_FLIP_VERSION:-1.7}"   # NVIDIA FLIP (PyPI flip-evaluator), the study's image metric

# A fresh venv at $1 with the PyPI requirement $2 installed ($3 names it in the message).
mapm_pypi_venv() {
  local venv="$1"
  command -v python3 >/dev/null 2>&1 || mapm_apt_install python3 python3-venv
  mkdir -p "$MAPM_CACHE"
  echo "mapm setup: installing $3 from PyPI into $venv ..." >&2
  rm -rf "$venv"
  { python3 -m venv "$venv" >/dev/null 2>&1 || { mapm_apt_install python3-venv && python3 -m venv "$venv" >/dev/null 2>&1; }; } \
    || mapm_die "could not create a Python venv at $venv"
  "$venv/bin/pip" install -q "$2" >&2 || mapm_die "pip install $2 failed"
}

mapm_ensure_yosys() {
  local venv="$MAPM_CACHE/pyosys-$MAPM_PYOSYS_VERSION"
  if ! "$venv/bin/python" -c 'from pyosys import libyosys' >/dev/null 2>&1; then
    mapm_pypi_venv "$venv" "pyosys==$MAPM_PYOSYS_VERSION" "pyosys $MAPM_PYOSYS_VERSION (yosys)"
    "$venv/bin/python" -c 'from pyosys import libyosys' >/dev/null 2>&1 || mapm_die "pyosys installed but does not import"
  fi
  echo "$venv/bin/python"
}

# NVIDIA's FLIP image-difference tool (PyPI flip-evaluator, a compiled wheel with a `flip`
# command) in its own venv; prints flip=PATH (read by mapm.evaluation.Flip).
mapm_ensure_flip() {
  local venv="$MAPM_CACHE/flip-$MAPM_FLIP_VERSION"
  if ! "$venv/bin/flip" -h >/dev/null 2>&1; then
    mapm_pypi_venv "$venv" "flip-evaluator==$MAPM_FLIP_VERSION" "FLIP $MAPM_FLIP_VERSION (flip-evaluator)"
    "$venv/bin/flip" -h >/dev/null 2>&1 || mapm_die "flip-evaluator installed but its flip command does not run"
  fi
  echo "flip=$venv/bin/flip"
}

mapm_ensure_opensta() {
  command -v sta >/dev/null 2>&1 || mapm_apt_install opensta
  command -v sta
}

# Prints the OSU018 Liberty file, unpacking Debian's qflow-tech-osu018 into the cache if needed.
mapm_ensure_osu018() {
  local dir="$MAPM_CACHE/osu018"
  local lib="$dir/usr/share/qflow/tech/osu018/osu018_stdcells.lib"
  if [ ! -s "$lib" ]; then
    command -v apt-get >/dev/null 2>&1 || mapm_die "cannot fetch qflow-tech-osu018 without apt-get; pass --lib FILE.lib"
    local tmp; tmp="$(mktemp -d)"
    echo "mapm setup: fetching the OSU 0.18 um cells (qflow-tech-osu018) from Debian's packages ..." >&2
    ( cd "$tmp" && { apt-get download -qq qflow-tech-osu018 >/dev/null 2>&1 || \
        { apt-get update -qq >/dev/null 2>&1 && apt-get download -qq qflow-tech-osu018 >/dev/null 2>&1; }; } ) \
      || { rm -rf "$tmp"; mapm_die "apt-get download qflow-tech-osu018 failed; pass --lib FILE.lib"; }
    mkdir -p "$dir" && dpkg-deb -x "$tmp"/qflow-tech-osu018_*.deb "$dir" || { rm -rf "$tmp"; mapm_die "could not unpack qflow-tech-osu018"; }
    rm -rf "$tmp"
    [ -s "$lib" ] || mapm_die "qflow-tech-osu018 has no $lib"
  fi
  echo "$lib"
}

# All three, as KEY=VALUE lines for tools/mapm cost (read by mapm.cost.CostTools).
mapm_ensure_cost_tools() {
  echo "yosys_python=$(mapm_ensure_yosys)"
  echo "sta=$(mapm_ensure_opensta)"
  echo "osu018_lib=$(mapm_ensure_osu018)"
}
