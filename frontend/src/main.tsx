import { StrictMode } from "react";
import { createRoot } from "react-dom/client";
import { BrowserRouter } from "react-router";

import "./i18n"; // the language is chosen before the first render
import { App } from "./App";
import { LiveProvider } from "./live/LiveProvider";
import { SessionGate } from "./session/SessionGate";
import "./styles/index.css";

const root = document.getElementById("root");
if (!root) throw new Error("index.html has no #root element");

createRoot(root).render(
  <StrictMode>
    <BrowserRouter>
      <SessionGate>
        <LiveProvider>
          <App />
        </LiveProvider>
      </SessionGate>
    </BrowserRouter>
  </StrictMode>,
);
