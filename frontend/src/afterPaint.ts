/**
 * Work that can wait for the screen: run once the next frame is painted (the task after its
 * animation frame callbacks), or after `latestMs` when no frame comes (a hidden page paints
 * none). A tap's mark is drawn first and its PUT and draft follow: on a phone slowed 4x the
 * request alone took a tenth of a tap's time to the screen (docs/slow-phone.md), and the
 * answer comes one frame later at most.
 */
export function afterPaint(work: () => void, latestMs = 100): void {
  let done = false;
  const run = (): void => {
    if (done) return;
    done = true;
    work();
  };
  const frames = typeof requestAnimationFrame === "function";
  if (frames) requestAnimationFrame(() => setTimeout(run, 0));
  setTimeout(run, frames ? latestMs : 0);
}
