/**
 * The app shell's service worker (vite.config.ts builds it: Workbox precaches index.html,
 * every chunk and the icons; it never answers the API or a photo): registered once the page
 * has loaded, and how a page moves to a new build.
 *
 * No stale mix: Workbox's precache keeps one build's files, all of them, and a worker that
 * is installed but waiting (the new build) does not touch what the active one serves. So an
 * open page keeps getting its own build's lazily loaded chunks from the old worker. The page
 * moves on its own, with no prompt: once a new worker has installed (its whole build
 * cached) and the page holds nothing a reload would lose (busy.ts: a photo not sent yet),
 * it tells the worker to take over and reloads when it has, once. The reload runs the new
 * build only (index.html and its chunks from the new precache; the old entries are gone).
 * A net: a lazily loaded chunk that still fails to load reloads the page, as Vite's docs
 * advise, but only when the server says this build is gone (its index.html names another
 * entry: a server already on another build, no worker), and at most once in 10 s. A chunk
 * that failed for want of a signal never reloads: with no signal a reload lands on the
 * browser's error page, and the session is lost from view. The import's own caller copes
 * (the lens reader goes on without the lens). The first worker claims the page that
 * installed it (clientsClaim, vite.config.ts) with no reload: nothing older to mix with.
 */

import { pageHoldsUnsent } from "./busy";

/** The build, set at build time (VITE_APP_VERSION): shown on <html data-build>. */
export const BUILD: string = import.meta.env.VITE_APP_VERSION ?? "dev";
/** How often a page that holds an unsent photo asks again whether it may update, ms. */
const RETRY_MS = 2_000;
const RELOADED_KEY = "buddy-search.shell-reloaded";

export function startShell(): void {
  document.documentElement.dataset.build = BUILD;
  // Never prevented: the import fails now; the page reloads later if the build is gone.
  window.addEventListener("vite:preloadError", () => void reloadIfBuildGone(fetch, () => location.reload()));
  // The dev server serves no worker; a browser without them (or blocking them) runs as before.
  if (import.meta.env.DEV || !("serviceWorker" in navigator)) return;
  const start = (): void => void register(navigator.serviceWorker, () => location.reload());
  if (document.readyState === "complete") start();
  else window.addEventListener("load", start, { once: true });
}

/** Register the app's worker in `container` and move the page to each new build (`reload`). */
export async function register(container: ServiceWorkerContainer, reload: () => void): Promise<void> {
  const servedByWorker = container.controller !== null;
  let registration: ServiceWorkerRegistration | undefined;
  try {
    registration = await container.register("/sw.js", { scope: "/", updateViaCache: "none" });
  } catch {
    // refused (a private window, a site setting): the app works online as before
  }
  // (Playwright's "block" answers with no registration at all.)
  if (!registration) return;
  // The page reloads when a new worker takes it over: one this page asked to, or any, if
  // a worker served this page (another tab may have asked). Not when the first worker
  // claims a page no worker served (the first visit: nothing older to mix with).
  let asked = false;
  let reloading = false;
  container.addEventListener("controllerchange", () => {
    if (!(servedByWorker || asked) || reloading) return;
    reloading = true;
    reload();
  });
  const takeOver = (worker: ServiceWorker): void =>
    takeOverWhenIdle(worker, () => {
      asked = true;
    });
  if (registration.waiting && registration.active) takeOver(registration.waiting);
  registration.addEventListener("updatefound", () => {
    const worker = registration.installing;
    // An update only when another build's worker is active. The first install is none,
    // whatever the page's controller says by the time it is "installed": WebKitGTK told
    // that after the first worker had claimed the page (4 of 12 first visits in probes
    // reloaded, so asked before this check).
    const active = registration.active;
    if (!worker || !active || active === worker) return;
    worker.addEventListener("statechange", () => {
      if (worker.state === "installed") takeOver(worker);
    });
  });
  // A page kept open for hours (the stands) looks for a new build when shown again; with
  // no signal the check fails, quietly.
  document.addEventListener("visibilitychange", () => {
    if (document.visibilityState === "visible") registration?.update().catch(() => undefined);
  });
}

/** Tell `worker` (installed, waiting) to take over once no photo waits to be sent. */
function takeOverWhenIdle(worker: ServiceWorker, asking: () => void): void {
  if (pageHoldsUnsent()) {
    setTimeout(() => takeOverWhenIdle(worker, asking), RETRY_MS);
    return;
  }
  asking();
  // vite-plugin-pwa's prompt mode: the generated worker calls skipWaiting() on this message.
  worker.postMessage({ type: "SKIP_WAITING" });
}

/**
 * After a lazily loaded chunk failed: `reload` when the server, asked for index.html, names
 * an entry other than this page's (a new build; this one's chunks are gone). Not when the
 * server does not answer (no signal: a reload would show the browser's error page), not
 * when it names this build (the failure passes; the import is tried again when next
 * needed), not when the page holds what a reload would lose (a photo being prepared or not
 * sent), and not twice in 10 s (no loop). Resolves to whether it reloaded.
 */
export async function reloadIfBuildGone(get: typeof fetch, reload: () => void): Promise<boolean> {
  const entry = document.querySelector<HTMLScriptElement>("script[type=module][src]");
  if (!entry || pageHoldsUnsent()) return false;
  let index: string;
  try {
    // A query the worker's precache does not know, so the server itself answers.
    const response = await get(`/?build-check=${Date.now()}`, { cache: "no-store" });
    if (!response.ok) return false;
    index = await response.text();
  } catch {
    return false;
  }
  if (index.includes(new URL(entry.src, location.href).pathname) || pageHoldsUnsent()) return false;
  const now = Date.now();
  try {
    if (now - Number(sessionStorage.getItem(RELOADED_KEY) ?? 0) < 10_000) return false;
    sessionStorage.setItem(RELOADED_KEY, String(now));
  } catch {
    return false; // without storage a loop could not be told: stay
  }
  reload();
  return true;
}
