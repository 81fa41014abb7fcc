"""A generated block of a Markdown file: the lines between a begin and an end marker (HTML comments), which a
script rewrites from committed results and a ctest checks (scripts/results_table.py, relocalisation_tables.py,
raw_logs_table.py). Writes are atomic: a failure leaves the file as it was."""
import pathlib


def write_atomically(path, text):
    """Writes text to path through path.tmp, renamed when whole; a failure raises OSError and leaves no .tmp."""
    path = pathlib.Path(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        tmp.write_text(text)
        tmp.replace(path)
    except OSError:
        tmp.unlink(missing_ok=True)
        raise


def markers(name):
    return f"<!-- {name}:begin -->", f"<!-- {name}:end -->"


def split(path, name):
    """(text before the block's first line, the block, the text from its end marker on); exits naming the file
    when it cannot be read or has no such block."""
    begin, end = markers(name)
    try:
        text = pathlib.Path(path).read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise SystemExit(f"{path}: cannot read it ({e})")
    a, b = text.find(begin + "\n"), text.find(end)
    if a < 0 or b < a:
        raise SystemExit(f"{path}: no '{begin}' ... '{end}' block")
    a += len(begin) + 1
    return text[:a], text[a:b], text[b:]


def replace(path, name, body):
    """Rewrites the block `name` of `path` with `body` (whole lines)."""
    head, _, tail = split(path, name)
    write_atomically(path, head + body + tail)


def is_current(path, name, body):
    return split(path, name)[1] == body


def run(argv, name, make, command):
    """The command line of a script that makes the block `name`: [--readme FILE | --check FILE] ARGS. make(ARGS)
    returns (the block's body, more text to print after it). --readme also writes the body into FILE's block;
    --check prints nothing and exits 1 when FILE's block is not the body (`command` rewrites it)."""
    mode = None
    if argv and argv[0] in ("--readme", "--check"):
        if len(argv) < 2:
            raise SystemExit(f"{argv[0]} needs a file")
        mode, readme, argv = argv[0], argv[1], argv[2:]
    body, more = make(argv)
    if mode == "--check":
        if not is_current(readme, name, body):
            raise SystemExit(f"{readme}: the {name} table is not the one the committed results give "
                             f"({command} rewrites it)")
        return
    if mode:
        replace(readme, name, body)
    print(body + more, end="")
