// The Faults tab's types are the fault API's, in api/faults.ts (live/ and the fault banner use
// them too); re-exported so the tab's modules import them from beside them.
export type * from "../../api/faults";
