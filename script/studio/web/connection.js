// The link to the server: one WebSocket whose JSON messages (model, error, running, params) go
// to `onMessage`, each connection starting with a `hello` of ours (the server may be a new one,
// counting its models from 1 again); when it closes (the server stopped or restarted) it tries
// again every half second, so a page left open picks up a restarted server by itself. A model's
// files follow its message as binary messages (each layer's .glb, then each control mesh's
// edges); the model goes on with them as `files`, `received` saying when its message came.

export function connect(onMessage, onStatus) {
  let socket;
  let model = null; // a model message waiting for its files
  const open = () => {
    socket = new WebSocket(`ws://${location.host}/ws`);
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

// Sends the parameters (all of them) to the server, which runs the recipe again with them.
export async function sendParams(values) {
  const body = new URLSearchParams(values).toString();
  await fetch('/api/params', { method: 'POST', body, headers: { 'Content-Type': 'application/x-www-form-urlencoded' } });
}
