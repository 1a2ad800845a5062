// The link to the server: one WebSocket whose JSON messages (model, error, running, params) go
// to `onMessage`, each connection starting with a `hello` of ours (the server may be a new one,
// counting its models from 1 again); when it closes (the server stopped or restarted) it tries
// again every half second, so a page left open picks up a restarted server by itself.

export function connect(onMessage, onStatus) {
  let socket;
  const open = () => {
    socket = new WebSocket(`ws://${location.host}/ws`);
    socket.onopen = () => {
      onStatus('live');
      onMessage({ type: 'hello' });
    };
    socket.onmessage = (event) => onMessage(JSON.parse(event.data));
    socket.onclose = () => {
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
