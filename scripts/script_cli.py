"""What the scripts of scripts/ share: bad input is one line and exit status 2, outputs are
written whole or not at all, and a failed rtusim run is reported by its own first line."""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile


class ScriptError(Exception):
    """Bad input or a failed run: one line for the user, exit status 2."""


def guarded(main):
    """Runs main(); a ScriptError becomes `<script>: <line>` on stderr and exit status 2."""
    name = pathlib.Path(sys.argv[0]).name
    try:
        return main()
    except ScriptError as e:
        print(f"{name}: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


def positive_int(text):
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer")
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not >= 1")
    return value


class _Parser(argparse.ArgumentParser):
    """argparse's parser, its errors one line (`<script>: <option>: <what>`, exit 2; --help
    shows the usage)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: {message} (--help: usage)\n")


def parser(doc):
    """An ArgumentParser whose --help shows the script's whole docstring as written."""
    return _Parser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)


def existing_file(path, option):
    """`path` if it is a file; else a ScriptError naming `option`."""
    if not pathlib.Path(path).is_file():
        raise ScriptError(f"{option} {path}: not found (or not a file)")
    return path


def output_dir(path, option="--out"):
    """Makes the output directory; a ScriptError when it cannot be one."""
    path = pathlib.Path(path)
    if path.exists() and not path.is_dir():
        raise ScriptError(f"{option} {path}: exists and is not a directory")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ScriptError(f"{option} {path}: cannot create ({e.strerror})")
    if not os.access(path, os.W_OK):
        raise ScriptError(f"{option} {path}: not writable")
    return path


def _mode_for(path):
    """The mode `path` has, or a new file's (0666 less the umask): mkstemp's files are 0600."""
    try:
        return path.stat().st_mode & 0o7777
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _replace_through_temp(path, write_temp):
    """write_temp(tmp) writes a temporary file beside `path`, which then replaces `path` with
    `path`'s mode: a failure leaves an earlier `path` as it was, and is a ScriptError."""
    path = pathlib.Path(path)
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
        os.fchmod(fd, _mode_for(path))
        write_temp(fd, tmp)
        os.replace(tmp, path)
    except OSError as e:
        raise ScriptError(f"{path}: cannot write ({e.strerror or e})")
    finally:
        if tmp is not None:
            pathlib.Path(tmp).unlink(missing_ok=True)


def write_atomically(path, write):
    """Calls write(file) on a temporary file beside `path`, then renames it to `path`."""
    def write_temp(fd, _tmp):
        with os.fdopen(fd, "w", newline="") as f:
            write(f)
    _replace_through_temp(path, write_temp)


def save_figure(fig, path, **kwargs):
    """fig.savefig through a temporary file (an earlier chart stays if drawing fails)."""
    def write_temp(fd, tmp):
        os.close(fd)
        fig.savefig(tmp, **kwargs)
    _replace_through_temp(path, write_temp)


def run_rtusim(cmd, what):
    """Runs an rtusim command (stdout discarded); a failure is a ScriptError with `what` and the
    run's first stderr line."""
    try:
        r = subprocess.run([str(c) for c in cmd], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    except OSError as e:
        raise ScriptError(f"{cmd[0]}: cannot run ({e.strerror})")
    if r.returncode != 0:
        first = next((l for l in r.stderr.splitlines() if l.strip()), f"exit {r.returncode}")
        raise ScriptError(f"{what}: {first}")
