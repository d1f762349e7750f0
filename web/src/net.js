// The WebSocket to groundsim-web: JSON text messages with an "op" field
// (docs/front-end.md). Reconnects after a drop; handlers by op.
export class Connection {
  constructor(url) {
    this.url = url;
    this.handlers = new Map();
    this.open = false;
    this.connect();
  }
  on(op, fn) { this.handlers.set(op, fn); return this; }
  connect() {
    const ws = new WebSocket(this.url);
    this.ws = ws;
    ws.onopen = () => { this.open = true; this.emit({ op: 'open' }); };
    ws.onclose = () => {
      this.open = false;
      this.emit({ op: 'close' });
      setTimeout(() => this.connect(), 1000);
    };
    ws.onmessage = (ev) => {
      let msg;
      try { msg = JSON.parse(ev.data); } catch { return; }
      this.emit(msg);
    };
  }
  emit(msg) {
    const fn = this.handlers.get(msg.op);
    if (fn) fn(msg);
    const any = this.handlers.get('*');
    if (any) any(msg);
  }
  send(msg) {
    if (this.open) this.ws.send(JSON.stringify(msg));
  }
}
