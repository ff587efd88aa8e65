"""The wslink client of the explorer's tests (taxel.explore.client), with the tests' ceiling."""

from __future__ import annotations

from functools import partial

from waits import CEILING

from taxel.explore import client as _client

HandshakeRefused = _client.HandshakeRefused
Client = partial(_client.Client, timeout=CEILING)
page_secret = partial(_client.page_secret, timeout=CEILING)
