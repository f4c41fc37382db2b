import * as assert from "node:assert/strict";
import { listingText } from "../../src/listing";

describe("listingText", () => {
  it("takes a string as it is, or the listing field of an object", () => {
    assert.equal(listingText("0000 PUSH 1\n"), "0000 PUSH 1\n");
    assert.equal(listingText({ listing: "L" }), "L");
    assert.equal(listingText({ text: "T" }), "T");
  });

  it("shows other answers as JSON and says when there is none", () => {
    assert.equal(listingText({ a: 1 }), '{\n  "a": 1\n}');
    assert.match(listingText(undefined), /no listing/);
  });
});
