import { VitePWA } from "vite-plugin-pwa";
import { defineConfig } from "vitest/config";
import palette from "../shared_solver/drawing/palette.json";

// Preact through esbuild's automatic JSX runtime: no Babel, no plugin.
// The API runs on the backend (`make run`: port 8000): the dev server forwards /api to it.
// The app reads two files it shares with the server, outside this folder: the palette
// (shared_solver/drawing/palette.json) and the limits (backend/limits.json).
// The app's theme colour (manifest, browser bar, splash screen, icon tile) is the palette's
// outline: the icons (docsgen/app_icons.py) are drawn from the same file.
const THEME_COLOUR = palette.outline;

export default defineConfig({
  esbuild: { jsx: "automatic", jsxImportSource: "preact" },
  plugins: [
    { name: "theme-colour", transformIndexHtml: (html: string) => html.replaceAll("%THEME_COLOUR%", THEME_COLOUR) },
    // V8's explicit compile hint (Chrome 136+; to other engines a comment): the entry chunk
    // is compiled whole while it streams in, off the main thread, rather than a function at
    // a time on its first call, which is during the first taps. Added once the chunk is
    // minified (the minifier drops comments); its first line, as V8 asks.
    {
      name: "compile-hint",
      enforce: "post",
      generateBundle(_options, bundle) {
        for (const file of Object.values(bundle)) {
          if (file.type === "chunk" && file.isEntry) file.code = `//# allFunctionsCalledOnLoad\n${file.code}`;
        }
      },
    },
    // Installable, and it opens with no signal (docs/app.md, "Installed and offline"): the
    // manifest and a Workbox service worker that precaches the built shell. The page
    // registers it itself (src/shell/), which also decides when a new one takes over.
    VitePWA({
      injectRegister: false,
      // No skipWaiting: a new worker waits until the page says so (src/shell/update.ts),
      // so an open page keeps being served its own build's chunks until it reloads.
      registerType: "prompt",
      manifest: {
        name: "Buddy Search",
        short_name: "Buddy Search",
        description: "Find your friend across the venue from two photos.",
        id: "/",
        start_url: "/",
        scope: "/",
        display: "standalone",
        orientation: "portrait",
        theme_color: THEME_COLOUR,
        background_color: THEME_COLOUR,
        icons: [
          { src: "/icon-192.png", sizes: "192x192", type: "image/png", purpose: "any" },
          { src: "/icon-512.png", sizes: "512x512", type: "image/png", purpose: "any" },
          { src: "/icon-maskable-512.png", sizes: "512x512", type: "image/png", purpose: "maskable" },
        ],
      },
      includeAssets: ["icon.svg"],
      workbox: {
        // The shell: the page and every chunk Vite wrote (lazily loaded ones and per-language
        // catalogues included: all under assets/); the plugin adds the manifest, its icons
        // and includeAssets. Never the API or a photo: no runtime caching at all, so every
        // request the precache does not hold goes to the network as if there were no worker.
        globPatterns: ["index.html", "assets/**/*.{js,css,json,woff2,svg,png,wasm}"],
        runtimeCaching: [],
        // The app's own addresses (/, /join/<code>, /s) answer the precached page offline;
        // the server's other pages are never the app's.
        navigateFallback: "/index.html",
        navigateFallbackDenylist: [/^\/api\//, /^\/docs/, /^\/openapi\.json/, /^\/healthz/],
        cleanupOutdatedCaches: true,
        // The first worker takes the page that installed it at once (nothing older to mix
        // with), so that page's lazily loaded chunks already come from the precache when
        // the signal goes. A later worker starts only when the page asks (src/shell/).
        clientsClaim: true,
        // One file to serve and to cache-bust (backend/frontend.py sends it with no-cache).
        inlineWorkboxRuntime: true,
        // The chunks are content-hashed: Workbox need not add a revision to their URLs.
        dontCacheBustURLsMatching: /^assets\//,
        sourcemap: false,
      },
    }),
  ],
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
