import { defineConfig } from "vitest/config";

// Preact through esbuild's automatic JSX runtime: no Babel, no plugin.
// The API runs on the backend (`make run`: port 8000): the dev server forwards /api to it.
// The app reads two files it shares with the server, outside this folder: the palette
// (shared_solver/drawing/palette.json) and the limits (backend/limits.json).
export default defineConfig({
  esbuild: { jsx: "automatic", jsxImportSource: "preact" },
  build: {
    outDir: "dist",
    assetsDir: "assets",
    target: "es2020",
    sourcemap: false,
  },
  server: {
    proxy: { "/api": { target: "http://127.0.0.1:8000", changeOrigin: false } },
    fs: { allow: [".", "../backend/limits.json", "../shared_solver/drawing/palette.json"] },
  },
  test: {
    environment: "node",
    // One module graph per worker thread, not a process per test file: the files are pure
    // modules whose tests undo their stubs (unstubGlobals below as a net), and isolating
    // 34 files cost 40 s of a 45 s run beside make test's suite (7 s without).
    pool: "threads",
    isolate: false,
    unstubGlobals: true,
    include: ["src/**/*.test.ts"],
    // The app's words in English, loaded once for every test file (src/i18n/testSetup.ts).
    setupFiles: ["src/i18n/testSetup.ts"],
    // The stylesheet as written (palette.test.ts reads it): vitest empties CSS otherwise.
    css: { include: [/styles\.css/] },
  },
});
