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
