"""The suite runs as on a fresh clone wherever it runs: no pytest cache (pytest.ini: ``-p
no:cacheprovider``) and no Hypothesis example database, so that no file a previous run left
behind (``.pytest_cache/``, ``.hypothesis/``) changes what runs or in which order."""

from __future__ import annotations

try:
    from hypothesis import settings
except ImportError:  # the test extra not installed: the property tests skip themselves
    pass
else:
    settings.register_profile("fresh-clone", database=None)
    settings.load_profile("fresh-clone")
