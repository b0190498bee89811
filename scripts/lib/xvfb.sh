# Sourced by the scripts that open the viewer headless. start_xvfb N [WxH]: starts a virtual X server on
# display :N (screen WxH, default 1024x1024), waits for its socket (up to 5 s), exports DISPLAY=:N and leaves its
# process id in $xvfb for the caller's EXIT trap to kill.
start_xvfb() {
  Xvfb ":$1" -screen 0 "${2:-1024x1024}x24" -nolisten tcp >/dev/null 2>&1 &
  xvfb=$!
  for _ in $(seq 50); do [ -S "/tmp/.X11-unix/X$1" ] && break; sleep 0.1; done
  export DISPLAY=":$1"
}
