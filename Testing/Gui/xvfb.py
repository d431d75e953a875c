"""A private virtual X display for one command (what `xvfb-run -a` does, made reliable).

    <python> xvfb.py [--xvfb <Xvfb>] [--screen 1280x1024x24] -- <command> [<args>...]

Why not plain `xvfb-run -a`: (1) an X server resets when its last client disconnects, and a
client connecting during the reset is dropped ("bad X server connection. Aborting."). pvpython,
pvbatch and paraview connect briefly at start-up (hwloc's GL probe of displays :0-:9 and
$DISPLAY, during MPI initialization), so their render window failed now and then, mostly under
ctest -j; Xvfb runs here with -noreset. (2) xvfb-run -a picks
the display number before starting Xvfb, so runs started together can pick the same one; here
the number is random in [1000, 30000) (lock and socket checked, another one tried if Xvfb
finds it taken) and -displayfd reports when the server is ready. (3) xvfb-run leaves its Xvfb
running when its temporary folder vanished before its clean-up; here Xvfb is always stopped.

The command runs with DISPLAY set and its exit code is returned. Without Xvfb the command runs
on the current DISPLAY; with neither, exit code 77 (ctest SKIP_RETURN_CODE). Also importable:
`with VirtualDisplay(xvfb) as virtual: ... virtual.display ...`.
"""
import os
import random
import shutil
import subprocess
import sys
import tempfile

SKIP = 77


class VirtualDisplay:
    """Starts Xvfb on a free display (its number read back through -displayfd); stops it on
    exit. `display` is ":<n>", or None when no Xvfb could be found (then nothing is started)."""

    def __init__(self, xvfb=None, screen="1280x1024x24"):
        self.xvfb = xvfb or shutil.which("Xvfb")
        self.screen = screen
        self.display = None
        self._process = None
        self._log = None

    def __enter__(self):
        if not self.xvfb:
            return self
        # A random display number away from :0-:9 (which hwloc's probe connects to), skipped
        # when its lock or socket exists; -displayfd tells when the server is ready.
        numbers = random.SystemRandom()
        errors = []
        for _attempt in range(20):
            number = numbers.randrange(1000, 30000)
            if any(os.path.exists(path % number)
                   for path in ("/tmp/.X%d-lock", "/tmp/.X11-unix/X%d")):
                continue
            ready = self._start(number)
            if ready:
                self.display = ":%d" % number
                return self
            self._process.wait(timeout=10)
            self._log.seek(0)
            errors.append(self._log.read().decode(errors="replace"))
            self._process = None
        raise RuntimeError("Xvfb did not start: " + (errors[-1].strip() if errors else
                                                       "no free display number"))

    def _start(self, number):
        """Starts Xvfb on :number; True once it accepts connections, False if it exited."""
        read_end, write_end = os.pipe()
        self._log = tempfile.TemporaryFile()  # Xvfb's messages, read if it fails to start
        try:
            self._process = subprocess.Popen(
                [self.xvfb, ":%d" % number, "-displayfd", str(write_end), "-screen", "0",
                 self.screen, "-nolisten", "tcp", "-noreset"],
                pass_fds=(write_end,), stdout=subprocess.DEVNULL, stderr=self._log)
        finally:
            os.close(write_end)
        written = b""
        with os.fdopen(read_end, "rb") as pipe:
            while not written.endswith(b"\n"):
                chunk = pipe.read(1)
                if not chunk:
                    break
                written += chunk
        return written.strip() == str(number).encode()

    def __exit__(self, *exc):
        if self._process:
            self._process.terminate()
            try:
                self._process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        if self._log:
            self._log.close()
        return False


def main(argv):
    xvfb, screen = None, "1280x1024x24"
    while argv and argv[0] != "--":
        option = argv.pop(0)
        if option == "--xvfb":
            xvfb = argv.pop(0)
        elif option == "--screen":
            screen = argv.pop(0)
        else:
            print("unknown option " + option, file=sys.stderr)
            return 2
    command = argv[1:]
    if not command:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    with VirtualDisplay(xvfb, screen) as virtual:
        env = dict(os.environ)
        if virtual.display:
            env["DISPLAY"] = virtual.display
            env.pop("XAUTHORITY", None)
        elif not env.get("DISPLAY"):
            print("skipped: no Xvfb and no DISPLAY to run %s in" % command[0])
            return SKIP
        sys.stdout.flush()
        return subprocess.call(command, env=env)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
