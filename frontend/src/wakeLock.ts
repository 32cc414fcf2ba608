/**
 * Keeps the screen on while the phone waits for the other one (Screen Wake Lock API).
 * The browser drops the lock when the page is hidden; it is taken again when it shows.
 * Where the API is missing (or refused) nothing happens.
 */

interface WakeLockSentinelLike {
  released: boolean;
  release(): Promise<void>;
}

interface WakeLockLike {
  request(type: "screen"): Promise<WakeLockSentinelLike>;
}

export function keepAwake(): () => void {
  const wakeLock = (navigator as Navigator & { wakeLock?: WakeLockLike }).wakeLock;
  if (!wakeLock) return () => undefined;
  let sentinel: WakeLockSentinelLike | null = null;
  let active = true;
  const acquire = (): void => {
    if (!active || document.visibilityState !== "visible") return;
    if (sentinel && !sentinel.released) return;
    wakeLock.request("screen").then(
      (lock) => {
        if (active) sentinel = lock;
        else void lock.release().catch(() => undefined);
      },
      () => undefined, // refused (battery saver, no user gesture yet): fine
    );
  };
  const onVisible = (): void => acquire();
  document.addEventListener("visibilitychange", onVisible);
  // Some browsers grant the lock only after a touch: try again on each one (cheap when held).
  document.addEventListener("pointerdown", onVisible);
  acquire();
  return () => {
    active = false;
    document.removeEventListener("visibilitychange", onVisible);
    document.removeEventListener("pointerdown", onVisible);
    if (sentinel && !sentinel.released) void sentinel.release().catch(() => undefined);
    sentinel = null;
  };
}
