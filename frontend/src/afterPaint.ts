/**
 * Work that can wait for the screen: run once the next frame is painted, behind whatever
 * else the page has to do then (the next tap's events, a frame), or after `latestMs` when
 * no frame comes (a hidden page paints none). A tap's mark is drawn first and its draft
 * (localStorage) follows; its PUT goes at once, since the answer waits for it.
 *
 * After the frame's animation frame callbacks, the work is posted as a background task
 * where the browser has the Prioritized Task Scheduling API (Chromium), so that a task
 * queued for the same moment, a finger's next event among them, goes first; elsewhere
 * (Safari) it is the task after the frame. `latestMs` bounds the wait either way.
 */
export function afterPaint(work: () => void, latestMs = 100): void {
  let done = false;
  const run = (): void => {
    if (done) return;
    done = true;
    work();
  };
  const frames = typeof requestAnimationFrame === "function";
  if (frames) requestAnimationFrame(() => later(run));
  setTimeout(run, frames ? latestMs : 0);
}

interface Scheduler {
  postTask(task: () => void, options: { priority: "background" }): Promise<unknown>;
}

/** `run` as a background task (Prioritized Task Scheduling), else as the next task. */
function later(run: () => void): void {
  const scheduler = (globalThis as { scheduler?: Scheduler }).scheduler;
  if (scheduler && typeof scheduler.postTask === "function") {
    scheduler.postTask(run, { priority: "background" }).catch(() => setTimeout(run, 0));
  } else {
    setTimeout(run, 0);
  }
}
