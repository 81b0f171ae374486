"""swarm_forage_examples' Python controllers, run in process by swarm_forage (docs/python-controllers.md)."""
