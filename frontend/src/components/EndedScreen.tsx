import type { Ending } from "../session";

export function EndedScreen({ ending, onStart }: { ending: Ending; onStart: () => void }) {
  return (
    <main class="screen ended" data-testid="ended">
      <div class="ended-body">
        <h1>Session ended</h1>
        <p class="lead">
          {ending === "deleted"
            ? "Deleted for both phones: photos, taps and the answer are gone."
            : "Your friend ended the search, or its time ran out. Photos and taps are deleted."}
        </p>
      </div>
      <div class="bottom-actions">
        <button type="button" class="button primary huge" onClick={onStart}>
          Start again
        </button>
      </div>
    </main>
  );
}
