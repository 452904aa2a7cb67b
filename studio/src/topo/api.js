// The editor's requests to the studio's topological-grammar API (crates/shapegram-server,
// studio/topo): JSON in, JSON out; `pending` counts requests in flight for the status line and
// the browser tests.
export const requests = { pending: 0 };

/** POSTs `body` to `/api/topo/{name}`; resolves with the status and the JSON answer. */
export async function post(name, body) {
  requests.pending += 1;
  try {
    const response = await fetch(`/api/topo/${name}`, {
      method: "POST",
      headers: { "content-type": "application/json" },
      body: JSON.stringify(body),
    });
    return { status: response.status, json: await response.json() };
  } catch (e) {
    return { status: 0, json: { error: `cannot reach the studio: ${e.message}` } };
  } finally {
    requests.pending -= 1;
  }
}
