import type { ReactNode } from "react";
import { Link, Navigate, Route, Routes } from "react-router";

import { FaultBanner } from "./components/FaultBanner";
import { useTranslation } from "./i18n";
import { NodeLayout, NodeTabElement } from "./nav/NodeLayout";
import { NODE_TABS, TOP_PAGES } from "./nav/routes";
import { Sidebar } from "./nav/Sidebar";

function NotFound(): ReactNode {
  const { t } = useTranslation();
  return (
    <section className="page">
      <h1>{t("nav.notFound")}</h1>
      <p>
        <Link to="/">{t("nav.backToNetwork")}</Link>
      </p>
    </section>
  );
}

/** The shell: sidebar on the left, the routed page on the right. */
export function App(): ReactNode {
  return (
    <div className="app">
      <Sidebar />
      <main className="main">
        <FaultBanner />
        <Routes>
          {TOP_PAGES.map(({ path, Component }) => (
            <Route key={path} path={path} element={<Component />} />
          ))}
          <Route path="/nodes/:node" element={<NodeLayout />}>
            <Route index element={<Navigate to={NODE_TABS[0]?.path ?? ""} replace />} />
            {NODE_TABS.map((tab) => (
              <Route
                key={tab.path}
                path={tab.path}
                element={<NodeTabElement Component={tab.Component} />}
              />
            ))}
          </Route>
          <Route path="*" element={<NotFound />} />
        </Routes>
      </main>
    </div>
  );
}
