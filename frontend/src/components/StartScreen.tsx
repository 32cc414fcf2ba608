/** Start: "Start a search" makes a session; the code a friend gives joins theirs. */

import { useState } from "preact/hooks";
import { createSession, joinSession } from "../api";
import { t } from "../i18n";
import { LanguageSwitch } from "../i18n/LanguageSwitch";
import { errorText } from "../i18n/server";
import { codeFrom } from "../joinCode";
import { CODE_DIGITS } from "../limits";
import type { Credentials } from "../types";

interface Props {
  resume: Credentials | null;
  onResume: () => void;
  onEnter: (credentials: Credentials) => void;
  initialCode: string;
  initialError: string | null;
}

export function StartScreen({ resume, onResume, onEnter, initialCode, initialError }: Props) {
  const [code, setCode] = useState(initialCode);
  const [error, setError] = useState<string | null>(initialError);
  const [busy, setBusy] = useState<"start" | "join" | null>(null);

  const start = async (): Promise<void> => {
    setBusy("start");
    setError(null);
    try {
      const created = await createSession();
      onEnter({ session_id: created.session_id, token: created.token, role: created.role });
    } catch (failure) {
      setError(errorText(failure));
      setBusy(null);
    }
  };

  const join = async (event: Event): Promise<void> => {
    event.preventDefault();
    const digits = codeFrom(code);
    if (digits === null) {
      setError(t("start.codeDigits", { digits: CODE_DIGITS }));
      return;
    }
    setBusy("join");
    setError(null);
    try {
      const joined = await joinSession(digits);
      onEnter({ session_id: joined.session_id, token: joined.token, role: joined.role });
    } catch (failure) {
      setError(errorText(failure));
      setBusy(null);
    }
  };

  return (
    <main class="screen start">
      <header class="start-head">
        <LanguageSwitch />
        <h1>
          Buddy<span class="accent"> Search</span>
        </h1>
        <p class="lead">{t("start.lead")}</p>
      </header>

      {resume && (
        <button type="button" class="button secondary wide" onClick={onResume}>
          {t("start.resume")}
        </button>
      )}

      <form class="join" onSubmit={join}>
        <label for="join-code" class="label">
          {t("start.joinLabel")}
        </label>
        <div class="join-row">
          <input
            id="join-code"
            data-testid="join-code"
            class="code-input"
            inputMode="numeric"
            autoComplete="one-time-code"
            pattern="[0-9 ]*"
            maxLength={CODE_DIGITS + 2}
            placeholder="1234 5678"
            value={code}
            onInput={(event) => setCode((event.target as HTMLInputElement).value)}
          />
          <button type="submit" data-testid="join" class="button secondary" disabled={busy !== null}>
            {busy === "join" ? t("start.joining") : t("start.join")}
          </button>
        </div>
      </form>

      {error && (
        <p class="error" role="alert">
          {error}
        </p>
      )}

      <div class="bottom-actions">
        <button
          type="button"
          data-testid="start"
          class="button primary huge"
          disabled={busy !== null}
          onClick={() => void start()}
        >
          {busy === "start" ? t("start.starting") : t("start.start")}
        </button>
      </div>
    </main>
  );
}
