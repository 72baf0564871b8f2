"""`--json` keeps stdout pure JSON: whatever a command prints beside its document goes to stderr."""

import json

from modalfe.cli.main import _split_json


def test_the_document_is_split_from_messages_around_it():
    text = 'figure written to x.png\n{\n  "a": [1, 2]\n}\nnote: done\n'
    document, rest = _split_json(text)
    assert json.loads(document) == {"a": [1, 2]}
    assert "figure written" in rest and "note: done" in rest and "{" not in rest


def test_no_document_leaves_everything_for_stderr():
    assert _split_json("just words\n[not json\n") == (None, "just words\n[not json\n")
