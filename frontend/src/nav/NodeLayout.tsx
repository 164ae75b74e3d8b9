import type { ComponentType, ReactNode } from "react";
import { NavLink, Outlet, useParams } from "react-router";

import { NmtBadge } from "../components/NmtDot";
import { useTranslation } from "../i18n";
import { nodeTitle } from "../lib/format";
import { useLive } from "../live/context";
import { nodeUrl } from "./paths";
import { NODE_TABS } from "./routes";

export function parseNodeId(text: string | undefined): number | null {
  if (!text || !/^\d{1,3}$/.test(text)) return null;
  const node = Number(text);
  return node >= 1 && node <= 127 ? node : null;
}

/** Header with the node's name and live state, the tab bar, and the selected tab below. */
export function NodeLayout(): ReactNode {
  const { t } = useTranslation();
  const node = parseNodeId(useParams().node);
  const info = useLive((s) => s.infos.find((i) => i.node === node));
  const live = useLive((s) => (node === null ? undefined : s.nodes[node]));
  if (node === null) {
    return (
      <section className="page">
        <h1>{t("nav.unknownNode")}</h1>
        <p>{t("nav.nodeRange")}</p>
      </section>
    );
  }
  return (
    <section className="page">
      <header className="page-header">
        <h1>{nodeTitle(node, info)}</h1>
        <NmtBadge
          state={live?.nmt_state ?? info?.nmt_state ?? "unknown"}
          online={live?.online ?? info?.online ?? false}
        />
        {info && (
          <span className="muted small">
            {t(info.od_source === "upload" ? "nav.dictionaryImported" : "nav.dictionaryProfile", {
              file: info.od_filename,
            })}
          </span>
        )}
      </header>
      <nav className="tabs" aria-label={t("nav.nodePages")}>
        {NODE_TABS.map((tab) => (
          <NavLink key={tab.path} to={nodeUrl(node, tab.path)} className="tab">
            {t(tab.labelKey)}
          </NavLink>
        ))}
      </nav>
      <Outlet />
    </section>
  );
}

/** Renders a tab's page for the node in the URL; keyed so a node switch starts it fresh. */
export function NodeTabElement({
  Component,
}: {
  Component: ComponentType<{ node: number }>;
}): ReactNode {
  const node = parseNodeId(useParams().node);
  if (node === null) return null;
  return <Component key={node} node={node} />;
}
