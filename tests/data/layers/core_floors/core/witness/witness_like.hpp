// A fixture: a witness floor header.
#pragma once
