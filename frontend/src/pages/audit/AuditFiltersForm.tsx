import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import type { AuditFilters } from "./types";

export const NO_FILTERS: AuditFilters = { node: "", since: "", user: "", action: "" };

// Offered as suggestions; the server may log others, which can be typed.
const KNOWN_ACTIONS = [
  "sdo-write",
  "param",
  "pdo-apply",
  "dcf-load",
  "nmt",
  "drive-enable",
  "jog",
  "jog-stop",
  "quick-stop",
  "undo",
];

/** Node, since, user, action: applied together, so the list and the export agree. */
export function AuditFiltersForm({
  applied,
  onApply,
}: {
  applied: AuditFilters;
  onApply: (filters: AuditFilters) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const [draft, setDraft] = useState(applied);
  const set = (name: keyof AuditFilters) => (event: { target: { value: string } }) =>
    setDraft((d) => ({ ...d, [name]: event.target.value }));

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    onApply(draft);
  }

  return (
    <form className="audit-filters" onSubmit={submit} aria-label={t("logs.audit.filters.label")}>
      <label htmlFor={`${id}-node`}>{t("logs.audit.filters.node")}</label>
      <input
        id={`${id}-node`}
        className="audit-node"
        inputMode="numeric"
        placeholder={t("logs.audit.filters.anyNode")}
        value={draft.node}
        onChange={set("node")}
      />
      <label htmlFor={`${id}-since`}>{t("logs.audit.filters.since")}</label>
      <input id={`${id}-since`} type="datetime-local" value={draft.since} onChange={set("since")} />
      <label htmlFor={`${id}-user`}>{t("logs.audit.filters.user")}</label>
      <input
        id={`${id}-user`}
        placeholder={t("logs.audit.filters.anyone")}
        value={draft.user}
        onChange={set("user")}
      />
      <label htmlFor={`${id}-action`}>{t("logs.audit.filters.action")}</label>
      <input
        id={`${id}-action`}
        list={`${id}-actions`}
        placeholder={t("logs.audit.filters.anyAction")}
        value={draft.action}
        onChange={set("action")}
      />
      <datalist id={`${id}-actions`}>
        {KNOWN_ACTIONS.map((a) => (
          <option key={a} value={a} />
        ))}
      </datalist>
      <button type="submit" className="primary">
        {t("logs.audit.filters.apply")}
      </button>
      <button
        type="button"
        onClick={() => {
          setDraft(NO_FILTERS);
          onApply(NO_FILTERS);
        }}
      >
        {t("logs.audit.filters.clear")}
      </button>
    </form>
  );
}
