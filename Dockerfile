# Buddy Search in one image: the phone app built with Node, served by the Python app.
# docker-compose.yml runs it behind nginx with PostgreSQL (README.md, "Deploy").

# Stage 1: the phone app. The lock file first, so `npm ci` is cached until it changes. The
# app reads the palette and the limits it shares with the server from their own files, at
# the same places beside it as in the repository.
FROM node:20-slim AS frontend
WORKDIR /build/frontend
COPY frontend/package.json frontend/package-lock.json ./
RUN npm ci --no-audit --no-fund
COPY backend/limits.json /build/backend/
COPY shared_solver/drawing/palette.json /build/shared_solver/drawing/
COPY frontend/ ./
RUN npm run build

# Stage 2: the runtime: Python and the app, no Node, no compilers, no test packages.
FROM python:3.11-slim
ENV PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1
WORKDIR /app
# The locked runtime dependencies (every transitive package, with its hashes; not the test
# extras), installed before the code is copied so that a change to the code does not
# reinstall them. The app itself is not pip-installed: it runs from /app, where it finds
# frontend/dist beside backend/.
COPY requirements/runtime.txt requirements.txt
RUN pip install --require-hashes --no-deps -r requirements.txt && rm requirements.txt
COPY backend/ backend/
COPY shared_solver/ shared_solver/
COPY --from=frontend /build/frontend/dist frontend/dist
# Byte-code compiled now: the app's user cannot write to /app. var/ is where SQLite goes when
# no BUDDY_DATABASE_URL is given (a single `docker run`), so that user owns it.
RUN python -m compileall -q backend shared_solver \
    && useradd --system --uid 10001 --no-create-home --home-dir /app buddy \
    && mkdir var && chown buddy var
# Numeric, so that an orchestrator can check it is not root without reading /etc/passwd.
USER 10001

EXPOSE 8000
# curl is not in the slim image; urlopen raises on a 503 (database gone), so the check fails.
HEALTHCHECK --interval=10s --timeout=3s --start-period=30s --retries=3 \
    CMD ["python", "-c", "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/healthz', timeout=2)"]
# Behind nginx only: the proxy headers (client address, https) are trusted from any address
# because the replicas publish no port; nothing but nginx reaches them. No access log: event
# streams and pictures carry the session token in their URL. Event streams never end by
# themselves, so a stop waits 3 s for them, not forever.
CMD ["uvicorn", "backend.main:app", "--host", "0.0.0.0", "--port", "8000", \
     "--proxy-headers", "--forwarded-allow-ips", "*", "--no-access-log", \
     "--timeout-graceful-shutdown", "3"]
