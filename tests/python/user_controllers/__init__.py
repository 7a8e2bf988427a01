"""Controllers a study names by import path (``user_controllers.factories:...``);
the tests put this folder's parent on PYTHONPATH for the workers."""
