import pytest
from own_houses import make_own_houses


@pytest.fixture(scope="session")
def made(tmp_path_factory, cache_dir):
    """A folder with ``houses/`` (two small generated houses) and ``my-suite.json`` made from
    them by ``objsearch suite make`` (tests copy what they change)."""
    return make_own_houses(tmp_path_factory.mktemp("own-houses"), cache_dir)
