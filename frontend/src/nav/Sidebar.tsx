import { memo, type ReactNode } from "react";
import { NavLink, useLocation } from "react-router";

import type { NodeInfo } from "../api/types";
import { LanguageSelect } from "../components/LanguageSelect";
import { NmtDot } from "../components/NmtDot";
import { useTranslation, type MessageKey } from "../i18n";
import { nodeTitle } from "../lib/format";
import { useLive } from "../live/context";
import type { LinkStatus } from "../live/store";
import { SessionBadge } from "../session/SessionBadge";
import { nodeUrl } from "./paths";
import { NODE_TABS, TOP_PAGES, type TopPage } from "./routes";

function TopLink({ page }: { page: TopPage }): ReactNode {
  const { t } = useTranslation();
  return (
    <li>
      <NavLink to={page.path} end className="nav-link">
        {t(page.labelKey)}
      </NavLink>
    </li>
  );
}

// One entry per node; memo + a live slice per node, so a 5 Hz update of node 2 does not
// re-render node 1's entry.
const NodeEntry = memo(function NodeEntry({
  node,
  info,
}: {
  node: number;
  info: NodeInfo | undefined;
}): ReactNode {
  const { t } = useTranslation(); // memo: the language is not a prop, so subscribe here
  const live = useLive((s) => s.nodes[node]);
  const { pathname } = useLocation();
  const active = pathname.startsWith(`/nodes/${node}/`);
  const state = live?.nmt_state ?? info?.nmt_state ?? "unknown";
  const online = live?.online ?? info?.online ?? false;
  const title = nodeTitle(node, info);
  return (
    <li>
      <NavLink
        to={nodeUrl(node)}
        className={`nav-link node-link${active ? " active" : ""}`}
        aria-current={active ? "page" : undefined}
        title={title}
      >
        <NmtDot state={state} online={online} />
        <span className="node-link-text">{title}</span>
      </NavLink>
      {active && (
        <ul className="nav-sub">
          {NODE_TABS.map((tab) => (
            <li key={tab.path}>
              <NavLink to={nodeUrl(node, tab.path)} className="nav-link sub">
                {t(tab.labelKey)}
              </NavLink>
            </li>
          ))}
        </ul>
      )}
    </li>
  );
});

function linkText(link: LinkStatus): { key: MessageKey; attempt?: number } {
  switch (link.state) {
    case "open":
      return { key: "live.connected" };
    case "connecting":
      return link.attempt > 0
        ? { key: "live.reconnecting", attempt: link.attempt + 1 }
        : { key: "live.connecting" };
    case "closed":
      return { key: link.retryAt ? "live.retrying" : "live.disconnected" };
  }
}

function LinkIndicator(): ReactNode {
  const { t } = useTranslation();
  const link = useLive((s) => s.link);
  const { key, attempt } = linkText(link);
  return (
    <p className={`live-link live-${link.state}`} role="status" aria-live="polite">
      <span className="dot" aria-hidden="true" />
      {t(key, { attempt })}
    </p>
  );
}

export function Sidebar(): ReactNode {
  const { t } = useTranslation();
  const infos = useLive((s) => s.infos);
  const liveIds = useLive((s) => s.liveIds);
  const byId = new Map(infos.map((i) => [i.node, i]));
  const ids = [...new Set([...byId.keys(), ...liveIds])].sort((a, b) => a - b);
  return (
    <nav className="sidebar" aria-label={t("nav.main")}>
      <div className="brand">
        <span className="brand-mark" aria-hidden="true">
          ◎
        </span>
        ServoDesk
      </div>
      <ul className="nav-list">
        {TOP_PAGES.filter((p) => p.placement === "before-nodes").map((page) => (
          <TopLink key={page.path} page={page} />
        ))}
      </ul>
      <h2 className="nav-heading">{t("nav.nodes")}</h2>
      {ids.length === 0 ? (
        <p className="nav-empty">{t("nav.noNodes")}</p>
      ) : (
        <ul className="nav-list" aria-label={t("nav.nodes")}>
          {ids.map((id) => (
            <NodeEntry key={id} node={id} info={byId.get(id)} />
          ))}
        </ul>
      )}
      <ul className="nav-list nav-bottom">
        {TOP_PAGES.filter((p) => p.placement === "after-nodes").map((page) => (
          <TopLink key={page.path} page={page} />
        ))}
      </ul>
      <LinkIndicator />
      <SessionBadge />
      <LanguageSelect className="sidebar-language" />
    </nav>
  );
}
