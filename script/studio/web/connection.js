// The link to the server: one WebSocket whose JSON messages (model, error, running, params) go
// to `onMessage`, each connection starting with a `hello` of ours (the server may be a new one,
// counting its models from 1 again); when it closes (the server stopped or restarted) it tries
// again every half second, so a page left open picks up a restarted server by itself. A model's
// files follow its message as binary messages (each layer's .glb, then each control mesh's
// edges); the model goes on with them as `files`, `received` saying when its message came.
//
// The session's token (from the address the studio printed, `?token=…`) goes with the socket
// and every request; the socket's address also carries the page's parameters (the page's own
// address is the truth), and a change of them is sent over the socket: they are this page's,
// not every page's.

// The token of the address this page was opened at ('' when there is none).
export const token = new URLSearchParams(location.search).get('token') ?? '';

let socket = null;

// `params()` gives the page's parameters when a connection opens.
export function connect(onMessage, onStatus, params) {
  let model = null; // a model message waiting for its files
  const open = () => {
    const query = new URLSearchParams({ ...params(), token }).toString();
    socket = new WebSocket(`ws://${location.host}/ws?${query}`);
    socket.binaryType = 'arraybuffer';
    socket.onopen = () => {
      onStatus('live');
      onMessage({ type: 'hello' });
    };
    socket.onmessage = (event) => {
      if (typeof event.data !== 'string') {
        if (!model) return;
        model.files.push(event.data);
        if (model.files.length === model.needed) {
          const { message, files } = model;
          model = null;
          onMessage({ ...message, files });
        }
        return;
      }
      const message = JSON.parse(event.data);
      message.received = Date.now();
      if (message.type === 'model') {
        const needed = message.layers.length + message.layers.filter((l) => l.control).length;
        model = { message, files: [], needed };
      } else {
        onMessage(message);
      }
    };
    socket.onclose = () => {
      model = null;
      onStatus('offline');
      setTimeout(open, 500);
    };
  };
  open();
}

// Sends this page's parameters (all of them) to the server, which runs the recipe with them
// for this page (a run it has already made is shown at once).
export function sendParams(values) {
  if (socket?.readyState === WebSocket.OPEN) socket.send(JSON.stringify({ type: 'params', values }));
}

// POSTs `body` as JSON to `path` with the token in its header (how the page asks for anything
// that acts: the server takes no token in the address for it); resolves to the answer's JSON.
export async function postJson(path, body) {
  const answer = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', 'X-Blocksmith-Token': token },
    body: JSON.stringify(body),
  });
  if (!answer.ok) throw new Error(`${path}: ${answer.status}`);
  return answer.json();
}
