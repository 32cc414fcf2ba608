"""The deployment without containers: a throwaway PostgreSQL server (``postgres``), a
certificate made at start-up (``tls``), Debian's nginx with ``deploy/nginx.conf``
(``nginx``), and the whole topology (``cluster``: ``make run-cluster``, the cluster tests
and the load benchmark). Not part of the app's image."""
