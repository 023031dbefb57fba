"""Print the corpus table (tests/descriptions/corpus.py) at the end of a pytest run that ran the
corpus test — also under xdist, where the test ran in a worker: it leaves the table in a file."""
import time

_START = time.time()


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    from tests.descriptions.corpus import TABLE_FILE

    if TABLE_FILE.is_file() and TABLE_FILE.stat().st_mtime >= _START:
        terminalreporter.write_sep("=", "robot description corpus (tests/descriptions/corpus.py)")
        terminalreporter.write_line(TABLE_FILE.read_text())
