// Unit-test setup: unmount rendered trees between tests (testing-library cleans up by itself
// only when test globals are enabled, which this project does not use).
import { cleanup } from "@testing-library/react";
import { afterEach } from "vitest";

afterEach(() => {
  cleanup();
});
