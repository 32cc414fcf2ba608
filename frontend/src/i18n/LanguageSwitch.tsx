/**
 * The language switch: a native picker (the phone's own list, accessible as it is) over a
 * short label, each language named in itself. Choosing one fetches its catalogue and
 * re-renders the app in place (useLanguage in App): nothing on the screen is lost.
 */

import { switchLanguage, t, useLanguage } from "./index";
import { LANGUAGES, isLanguage } from "./languages";
import "./switch.css";

/** `compact`: the globe only (the session's top bar has little room: with the language's
 * code beside it, "Friend online" gave way on a 390 px phone). */
export function LanguageSwitch({ compact = false }: { compact?: boolean }) {
  const language = useLanguage();
  return (
    <label class={`language-switch ${compact ? "compact" : ""}`} data-testid="language">
      <svg viewBox="0 0 24 24" aria-hidden="true" fill="none" stroke="currentColor" stroke-width="2">
        <circle cx="12" cy="12" r="9" />
        <path d="M3 12h18M12 3c2.5 2.7 3.8 5.7 3.8 9s-1.3 6.3-3.8 9c-2.5-2.7-3.8-5.7-3.8-9S9.5 5.7 12 3z" />
      </svg>
      {!compact && (
        <span class="language-shown" aria-hidden="true">
          {LANGUAGES[language]}
        </span>
      )}
      <select
        aria-label={t("app.language")}
        value={language}
        onChange={(event) => {
          const chosen = (event.target as HTMLSelectElement).value;
          // Offline with the catalogue not yet fetched: the language stays as it was.
          if (isLanguage(chosen)) switchLanguage(chosen).catch(() => undefined);
        }}
      >
        {Object.entries(LANGUAGES).map(([code, name]) => (
          <option key={code} value={code} lang={code}>
            {name}
          </option>
        ))}
      </select>
    </label>
  );
}
