import { defineConfig } from "vitest/config";

// Preact through esbuild's automatic JSX runtime: no Babel, no plugin.
// The API runs on the backend (port 8765 in development): the dev server forwards /api to it.
export default defineConfig({
  esbuild: { jsx: "automatic", jsxImportSource: "preact" },
  build: {
    outDir: "dist",
    assetsDir: "assets",
    target: "es2020",
    sourcemap: false,
  },
  server: {
    proxy: { "/api": { target: "http://127.0.0.1:8765", changeOrigin: false } },
  },
  test: {
    environment: "node",
    include: ["src/**/*.test.ts"],
  },
});
