import * as assert from "node:assert/strict";
import { listingText } from "../../src/listing";

describe("listingText", () => {
  it("takes the listing string as it is", () => {
    assert.equal(listingText("0000 PUSH 1\n"), "0000 PUSH 1\n");
  });

  it("rejects an answer that is not a listing", () => {
    assert.throws(() => listingText(undefined), /no listing/);
    assert.throws(() => listingText({ listing: "L" }), /no listing/);
  });
});
