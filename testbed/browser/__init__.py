"""The browser driver the end-to-end tests, ``make screenshots`` and the browser benchmarks
share: a :class:`~.phone.Phone` in Chromium (Playwright, :mod:`.chromium_phone`) or in
WebKit (Selenium and WebKitWebDriver, :mod:`.webkit_phone`), its accessibility audit
(:mod:`.audit`), and a search played with two of them (:mod:`.play`). Test-only pieces
(pytest fixtures, the pools that keep phones between tests) stay in ``tests/e2e``."""
