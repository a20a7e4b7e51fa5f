// A room page's socket, and what the page says when it closes: whether the room server refuses the
// link's token (asked at /r/ROOM/check, the token in a header), or is away for a moment (the page
// then tries again). The token never rides in an address, which proxies and access logs record: the
// socket offers it among its subprotocols (toonface/room/server.py's _token), /check in a header.
// Shared by the viewer and performer pages.
"use strict";
(() => {
  function open(room, role, token, query = "") {
    // the room's socket for ROLE, with QUERY ("&format=...") after the role
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    return new WebSocket(`${scheme}://${location.host}/r/${encodeURIComponent(room)}/ws?role=${role}${query}`,
                         ["toonface", `bearer.${token}`]);
  }

  async function closed(room, role, token) {
    // "none" (no token in the link), "refused" (the server says no to it) or "away"
    if (!token) return "none";
    try {
      const answer = await fetch(`/r/${encodeURIComponent(room)}/check?role=${role}`,
                                 {headers: {Authorization: `Bearer ${token}`}, cache: "no-store"});
      return answer.status === 403 ? "refused" : "away";
    } catch (error) {
      return "away";
    }
  }

  function said(state, role) {
    if (state === "none") {
      return `no ${role} token: open the link the room server printed (it ends in #${role}=…)`;
    }
    if (state === "refused") {
      return `the room server refuses this link's ${role} token: open the link it printed for this room `
        + "(a server started again without --tokens makes new ones); not trying again";
    }
    return "disconnected (the server is away): trying again…";
  }

  // a corrected link pasted into the same tab changes only the fragment: start again with it
  window.addEventListener("hashchange", () => location.reload());
  window.toonRoomLink = {open, closed, said};
})();
