// The app's pages as data: the sidebar, the router and the node tab bar are all built from
// these arrays, so a new page (Motion, PDO, Faults per node; a top-level Scope) is one entry.
// The top of the import graph: it imports every page, so nothing below imports it; a page links
// to another through nav/paths.ts (.dependency-cruiser.cjs holds the layers).
import type { ComponentType } from "react";

import type { MessageKey } from "../i18n";
import { AuditPage } from "../pages/audit/AuditPage";
import { CommissionPage } from "../pages/commission/CommissionPage";
import { DrivePage } from "../pages/drive/DrivePage";
import { FaultsPage } from "../pages/faults/FaultsPage";
import { LogsPage } from "../pages/logs/LogsPage";
import { NetworkPage } from "../pages/network/NetworkPage";
import { OdPage } from "../pages/od/OdPage";
import { ParamsPage } from "../pages/params/ParamsPage";
import { PdoPage } from "../pages/pdo/PdoPage";
import { ScopePage } from "../pages/scope/ScopePage";
import { ToolsPage } from "../pages/tools/ToolsPage";
import { FIRST_NODE_TAB } from "./paths";

export interface TopPage {
  /** Absolute URL path. */
  path: string;
  /** Catalogue key of the page's name. */
  labelKey: MessageKey;
  /** Where the sidebar lists it: above or below the per-node entries. */
  placement: "before-nodes" | "after-nodes";
  Component: ComponentType;
}

export interface NodeTab {
  /** Path under /nodes/:node/. */
  path: string;
  /** Catalogue key of the tab's name. */
  labelKey: MessageKey;
  Component: ComponentType<{ node: number }>;
}

export const TOP_PAGES: readonly TopPage[] = [
  { path: "/", labelKey: "nav.network", placement: "before-nodes", Component: NetworkPage },
  { path: "/scope", labelKey: "nav.scope", placement: "after-nodes", Component: ScopePage },
  { path: "/logs", labelKey: "nav.logs", placement: "after-nodes", Component: LogsPage },
  { path: "/audit", labelKey: "nav.audit", placement: "after-nodes", Component: AuditPage },
  { path: "/tools", labelKey: "nav.tools", placement: "after-nodes", Component: ToolsPage },
];

export const NODE_TABS: readonly NodeTab[] = [
  { path: FIRST_NODE_TAB, labelKey: "nav.parameters", Component: ParamsPage },
  { path: "od", labelKey: "nav.od", Component: OdPage },
  { path: "pdos", labelKey: "nav.pdos", Component: PdoPage },
  { path: "drive", labelKey: "nav.drive", Component: DrivePage },
  { path: "faults", labelKey: "nav.faults", Component: FaultsPage },
  { path: "commission", labelKey: "nav.commission", Component: CommissionPage },
];
