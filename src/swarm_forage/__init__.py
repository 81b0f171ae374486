"""swarm_forage's Python side: reading recorded runs and a sweep's tables (runs), drawing them (figures).
The generated message modules (swarm_forage.msg, swarm_forage.srv) live beside these in the devel space."""
