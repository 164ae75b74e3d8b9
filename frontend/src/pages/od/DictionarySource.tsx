import { useState, type ReactNode } from "react";

import { api, call, uploadBody } from "../../api/client";
import type { LintWarning, OdTree } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker, OD_FILE_TYPES } from "../../components/FilePicker";
import { LintTable } from "../../components/LintTable";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { shortPath } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";

interface Props {
  node: number;
  tree: OdTree | undefined;
  /** The node's dictionary changed: load it again. */
  onChanged: () => void;
}

/** Where the node's dictionary comes from; import an EDS for it or go back to the profile's. */
export function DictionarySource({ node, tree, onChanged }: Props): ReactNode {
  const { t } = useTranslation();
  const store = useLiveStore();
  const [showWarnings, setShowWarnings] = useState(false);
  const [imported, setImported] = useState<readonly LintWarning[] | null>(null);

  async function afterChange(summary: OdTree): Promise<void> {
    setImported(summary.source === "upload" ? summary.warnings : null);
    setShowWarnings(summary.source === "upload" && summary.warnings.length > 0);
    onChanged();
    // The sidebar and Network page show the dictionary's source per node.
    store.upsertInfo(await call(api.GET("/api/nodes/{node}", { params: { path: { node } } })));
  }

  const configure = useMay("configure");
  const load = useAction(async (file: File) => {
    const summary = await call(
      api.POST("/api/nodes/{node}/od", { params: { path: { node } }, ...uploadBody(file) }),
    );
    await afterChange(summary);
  });
  const revert = useAction(async () => {
    await afterChange(
      await call(api.DELETE("/api/nodes/{node}/od", { params: { path: { node } } })),
    );
  });

  const warnings = imported ?? tree?.warnings ?? [];
  const busy = load.busy || revert.busy;
  // A fragment: inside the page's wrapping toolbar the findings table takes a full row of
  // its own instead of squeezing beside the buttons.
  return (
    <>
      <div className="dictionary-source">
        <FilePicker
          label={t("od.source.loadEds")}
          accept={OD_FILE_TYPES}
          {...configure.gate(t("od.source.gateLoad"), { disabled: busy })}
          onFile={(f) => void load.run(f)}
        />
        <button
          type="button"
          onClick={() => void revert.run()}
          {...configure.gate(t("od.source.gateChange"), {
            disabled: busy || tree?.source !== "upload",
          })}
        >
          {t("od.source.useProfile")}
        </button>
        {busy && <Spinner label={t("od.page.loading")} />}
        {tree && (
          <span className="small" data-testid="od-source">
            {tree.source === "upload" ? t("od.source.imported") : t("od.source.profile")}:{" "}
            <span className="mono" title={tree.filename}>
              {shortPath(tree.filename)}
            </span>{" "}
            ·{" "}
            <button
              type="button"
              className="link-button"
              aria-expanded={showWarnings}
              onClick={() => setShowWarnings((v) => !v)}
            >
              {t("od.source.warnings", { count: warnings.length })}
            </button>
          </span>
        )}
      </div>
      {(load.error ?? revert.error) && (
        <div className="toolbar-panel">
          <ErrorText error={load.error ?? revert.error} />
        </div>
      )}
      {showWarnings && (
        <div className="toolbar-panel">
          <LintTable warnings={warnings} caption={t("od.source.warningsCaption")} />
        </div>
      )}
    </>
  );
}
