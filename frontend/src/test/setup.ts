// Unit-test setup: unmount rendered trees between tests (testing-library cleans up by itself
// only when test globals are enabled, which this project does not use).
import { cleanup, configure } from "@testing-library/react";
import { afterEach, beforeEach } from "vitest";

import { LANGUAGE_STORAGE_KEY, i18n } from "../i18n";

// findBy*/waitFor wait for what a user would see; on a busy 2-core machine a render after a
// fetch can take longer than testing-library's 1 s default without anything being wrong.
configure({ asyncUtilTimeout: 5000 });

// The tests read English (jsdom's browser language is en-US); a test that switches to Chinese
// does not carry it into the next one.
beforeEach(async () => {
  localStorage.removeItem(LANGUAGE_STORAGE_KEY);
  await i18n.changeLanguage("en");
});

afterEach(() => {
  cleanup();
});
