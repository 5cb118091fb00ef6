from peenflow.engine.fingerprint import source_fingerprint

BASE = '''
def flow_stress(eps):
    """Johnson-Cook."""
    return 1408e6 + 600.8e6 * eps ** 0.234
'''


def test_comments_docstrings_and_layout_do_not_change_the_fingerprint():
    cosmetic = '''
# a comment
def flow_stress(eps):
    """A different docstring, fixed typo."""

    return 1408e6 + 600.8e6 * eps ** 0.234   # trailing comment
'''
    assert source_fingerprint(BASE) == source_fingerprint(cosmetic)


def test_code_edits_change_the_fingerprint():
    assert source_fingerprint(BASE) != source_fingerprint(BASE.replace("0.234", "0.235"))
    assert source_fingerprint(BASE) != source_fingerprint(BASE.replace("eps ** 0.234", "eps"))


def test_threads_fingerprinting_at_once_do_not_trip_the_ast_constructor():
    """A dask.distributed worker runs tasks in threads, each fingerprinting its code. CPython 3.11's
    AST constructor keeps one recursion depth per interpreter, so two threads parsing at once (a
    finaliser run by the garbage collector mid-parse lets the other in) failed a CI run with
    "SystemError: AST constructor recursion depth mismatch"; every parse of the fingerprints goes
    through one lock."""
    import sys
    import threading
    import time
    from pathlib import Path

    from peenflow.engine import fingerprint

    source = Path(fingerprint.__file__).read_text(encoding="utf-8") * 3
    errors = []

    class Yields:
        def __del__(self):
            time.sleep(0)  # hand the GIL to another thread from inside the collector

    def work():
        for _ in range(40):
            cycles = [Yields() for _ in range(50)]
            for c in cycles:
                c.me = c  # garbage only the cycle collector frees, during the next parse's allocations
            del cycles
            try:
                fingerprint.source_fingerprint(source)
            except SystemError as e:
                errors.append(str(e))
                return

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        threads = [threading.Thread(target=work) for _ in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert errors == []
