import { useId, type ReactNode } from "react";

import { LANGUAGES, currentLanguage, setLanguage, useTranslation } from "../i18n";

/** "Language / 语言": switches the whole app at once and is remembered by this browser. */
export function LanguageSelect({ className }: { className?: string }): ReactNode {
  const { t } = useTranslation(); // re-renders on a switch, so the shown value follows
  const id = useId();
  return (
    <div className={className ? `language-select ${className}` : "language-select"}>
      <label htmlFor={id}>{t("language.label")}</label>
      <select
        id={id}
        value={currentLanguage()}
        onChange={(e) => {
          const picked = LANGUAGES.find((l) => l.code === e.target.value);
          if (picked) setLanguage(picked.code);
        }}
      >
        {LANGUAGES.map((l) => (
          <option key={l.code} value={l.code} lang={l.code}>
            {l.name}
          </option>
        ))}
      </select>
    </div>
  );
}
