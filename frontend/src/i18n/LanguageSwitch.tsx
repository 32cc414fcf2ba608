/**
 * The language switch: a native picker (the phone's own list, accessible as it is) over a
 * short label, each language named in itself. Choosing one fetches its catalogue and
 * re-renders the app in place (useLanguage in App): nothing on the screen is lost.
 */

import { switchLanguage, t, useLanguage } from "./index";
import { LANGUAGES, isLanguage } from "./languages";
import "./switch.css";

/** `compact`: the language's code only (the session's top bar has little room). */
export function LanguageSwitch({ compact = false }: { compact?: boolean }) {
  const language = useLanguage();
  return (
    <label class={`language-switch ${compact ? "compact" : ""}`} data-testid="language">
      <span class="language-shown" aria-hidden="true">
        {compact ? language.toUpperCase() : LANGUAGES[language]}
      </span>
      <select
        aria-label={t("app.language")}
        value={language}
        onChange={(event) => {
          const chosen = (event.target as HTMLSelectElement).value;
          if (isLanguage(chosen)) void switchLanguage(chosen);
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
